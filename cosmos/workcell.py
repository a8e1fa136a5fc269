"""The workcell: model files, home configuration, fixture frames and the tool.

Everything here is read from an arm's scene file (:attr:`cosmos.robots.Robot.scene_xml`,
``cosmos/models/<arm>/scene.xml``), so the XML stays the one place where the
workcell is defined: once per model, the values then kept in the user cache
(:mod:`cosmos.model_facts`: a run does not compile the scene for them). The
functions take the arm (the PUMA 560 by default); the module's constants are the PUMA's:

- :data:`HOME_Q`: the ``home`` keyframe, where every program starts;
- :func:`fixture_frames`: the predefined frames ``table``, ``hole``, ``slope``
  of the task language, z axis pointing into the surface (approach direction);
- :data:`TOOL`: what the controller may know about the tool (its datasheet):
  mass properties and the sensor and tool-point frames, relative to the flange;
- :data:`WRIST_SENSOR` and :data:`ARM_CAPABILITY`: the sensor's rating and what
  the arm can do at the tool (declared in :mod:`cosmos.capabilities`, below the
  language, which checks programs against them).

World frame = PUMA base frame: z up, origin on the floor on the joint-1 axis; the
Panda stands on its pedestal at the same origin.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from cosmos.capabilities import ARM_CAPABILITY as ARM_CAPABILITY
from cosmos.capabilities import WRIST_SENSOR as WRIST_SENSOR
from cosmos.errors import CosmosError
from cosmos.hand.gripper_scene import mount_gripper
from cosmos.hand.tool import Tool
from cosmos.model_facts import kept
from cosmos.robots import DEFAULT_ROBOT, PUMA560, Robot

MODEL_DIR: Path = PUMA560.model_dir
ARM_XML: Path = PUMA560.arm_xml
"""The bare PUMA 560 (no tool): the controller's model is built from it."""
SCENE_XML: Path = PUMA560.scene_xml
"""The workcell: arm with wrist sensor and peg, table, hole fixture, tilted plate."""

JOINT_NAMES = PUMA560.joint_names
"""The PUMA's hinge joints (and their motors, same names) in the order of q."""
FIXTURE_NAMES = ("table", "hole", "slope")
"""Sites of the scene that are predefined frames of the task language."""
FLANGE_SITE = "flange"
TOOL_BODY = "tool"
SENSOR_SITE = "ft_sensor"
TOOL_SITE = "tool"
FORCE_SENSOR = "ft_force"
TORQUE_SENSOR = "ft_torque"
HOME_KEY = "home"


def read_only(array: np.ndarray) -> np.ndarray:
    """A read-only float copy of ``array``: for constants that must not be mutated."""
    out = np.array(array, dtype=float)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class FixtureFrame:
    """A predefined frame of the workcell.

    Attributes:
        name: Name of the frame in programs (``table``, ``hole``, ``slope``).
        position: Origin in the world frame [m], ``(3,)``, read-only.
        rotation: Frame axes as columns in world coordinates (rotation from the
            fixture frame to the world frame), ``(3, 3)``, read-only. Its z axis
            points into the surface: the direction in which the tool approaches.
    """

    name: str
    position: np.ndarray  # (3,)
    rotation: np.ndarray  # (3, 3)


@dataclass(frozen=True)
class ToolSpec:
    """The tool as the controller knows it; every quantity is in the flange frame.

    The tool is everything beyond the wrist force/torque sensor's measuring
    plane: sensor housing (tool side), collar and peg. It is rigidly mounted on
    the last link (the PUMA's link 6: the flange frame is DH frame 6; the Panda's link 7: the
    URDF's panda_link8).

    Attributes:
        mass_kg: Mass [kg].
        com_in_flange: Centre of mass [m], ``(3,)``.
        inertia_in_flange: Rotational inertia about the centre of mass, flange
            axes [kg m^2], ``(3, 3)``.
        sensor_position_in_flange: Origin of the sensor's measuring frame [m], ``(3,)``.
        sensor_rotation_in_flange: Sensor axes in flange coordinates (rotation
            from the sensor frame to the flange frame), ``(3, 3)``.
        tool_position_in_flange: The tool point (peg tip) [m], ``(3,)``.
        tool_rotation_in_flange: Tool-frame axes in flange coordinates; z runs
            along the peg, away from the flange, ``(3, 3)``.
    """

    mass_kg: float
    com_in_flange: np.ndarray  # (3,)
    inertia_in_flange: np.ndarray  # (3, 3)
    sensor_position_in_flange: np.ndarray  # (3,)
    sensor_rotation_in_flange: np.ndarray  # (3, 3)
    tool_position_in_flange: np.ndarray  # (3,)
    tool_rotation_in_flange: np.ndarray  # (3, 3)


def _object_id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    index = mujoco.mj_name2id(model, kind, name)
    if index < 0:
        raise CosmosError(f"the scene has no {kind.name.removeprefix('mjOBJ_').lower()} '{name}'")
    return int(index)


def scene_spec(scene_xml: Path, tool: Tool = Tool.PEG, robot: str = "puma560") -> mujoco.MjSpec:
    """An arm's workcell as a spec, carrying ``tool`` (the scene file's peg, or the arm's gripper)."""
    spec = mujoco.MjSpec.from_file(str(scene_xml))
    if tool is Tool.GRIPPER:
        mount_gripper(spec, robot)
    return spec


def _scene_at_home(
    scene_xml: Path = SCENE_XML, tool: Tool = Tool.PEG, robot: str = "puma560"
) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The compiled scene with the kinematics evaluated at the home keyframe (compiled once)."""
    return _compiled_at_home(scene_xml, tool, robot)  # one cache key however the caller passes them


@functools.cache
def _compiled_at_home(scene_xml: Path, tool: Tool, robot: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = scene_spec(scene_xml, tool, robot).compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, _object_id(model, mujoco.mjtObj.mjOBJ_KEY, HOME_KEY))
    mujoco.mj_kinematics(model, data)
    return model, data


def scene_model(scene_xml: Path = SCENE_XML) -> mujoco.MjModel:
    """The arm's scene file compiled, with its peg (once per process: shared, not to be changed)."""
    return _scene_at_home(scene_xml)[0]


def home_tool_from_scene(scene_xml: Path = SCENE_XML) -> tuple[np.ndarray, np.ndarray]:
    """Where the tool point is at home, world [m] ``(3,)``, and its axes ``(3, 3)``: from the scene."""
    model, data = _scene_at_home(scene_xml)
    site = _object_id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
    return read_only(data.site_xpos[site]), read_only(data.site_xmat[site].reshape(3, 3))


def home_q_from_scene(robot: Robot = DEFAULT_ROBOT) -> np.ndarray:
    """The arm's home configuration [rad], ``(n,)``, read-only: compiled from its scene."""
    model, _ = _scene_at_home(robot.scene_xml)
    key = _object_id(model, mujoco.mjtObj.mjOBJ_KEY, HOME_KEY)
    return read_only(model.key_qpos[key])


@functools.cache
def home_q(robot: Robot = DEFAULT_ROBOT) -> np.ndarray:
    """The arm's home configuration [rad], ``(n,)``, read-only: its scene's ``home`` keyframe."""
    return kept(robot.scene_xml.parent, f"home_q:{robot.scene_xml.name}", lambda: home_q_from_scene(robot))


def _rotation(quat: np.ndarray) -> np.ndarray:
    """The rotation matrix of a MuJoCo quaternion (w, x, y, z)."""
    matrix = np.empty(9)
    mujoco.mju_quat2Mat(matrix, quat)
    return matrix.reshape(3, 3)


@functools.cache
def tool_spec(robot: Robot = DEFAULT_ROBOT, tool: Tool = Tool.PEG) -> ToolSpec:
    """The tool mounted on the arm's flange in its scene, as the controller is allowed to know it.

    The gripper's mass properties are those of the ``tool`` body and its fingers together,
    the fingers open (as at home).
    """
    name = f"tool_spec:{robot.name}:{robot.scene_xml.name}:{tool.value}"
    return kept(robot.scene_xml.parent, name, lambda: tool_spec_from_scene(robot, tool))


def tool_spec_from_scene(robot: Robot = DEFAULT_ROBOT, tool: Tool = Tool.PEG) -> ToolSpec:
    """:func:`tool_spec` computed from the compiled scene."""
    model, data = _scene_at_home(robot.scene_xml, tool, robot.name)
    flange = _object_id(model, mujoco.mjtObj.mjOBJ_SITE, FLANGE_SITE)
    body = _object_id(model, mujoco.mjtObj.mjOBJ_BODY, TOOL_BODY)
    sensor = _object_id(model, mujoco.mjtObj.mjOBJ_SITE, SENSOR_SITE)
    point = _object_id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
    if model.body_parentid[body] != model.site_bodyid[flange] or model.body_jntnum[body] != 0:
        raise CosmosError(f"body '{TOOL_BODY}' must be welded to the body of site '{FLANGE_SITE}'")
    if model.site_bodyid[sensor] != body or model.site_bodyid[point] != body:
        raise CosmosError(f"sites '{SENSOR_SITE}' and '{TOOL_SITE}' must be on body '{TOOL_BODY}'")
    # From the model's local poses, all relative to link 6 (the flange's body):
    # a point x of the tool body is at R_b x + p_b in link 6, at R_f^T (R_b x + p_b - p_f)
    # in the flange frame.
    rotation_flange = _rotation(model.site_quat[flange])
    rotation_body = rotation_flange.T @ _rotation(model.body_quat[body])
    origin_body = rotation_flange.T @ (model.body_pos[body] - model.site_pos[flange])

    def position_in_flange(point_in_body: np.ndarray) -> np.ndarray:
        return read_only(rotation_body @ point_in_body + origin_body)

    def rotation_in_flange(quat_in_body: np.ndarray) -> np.ndarray:
        return read_only(rotation_body @ _rotation(quat_in_body))

    if model.body_subtreemass[body] == model.body_mass[body]:  # one rigid body: its own inertial
        principal_axes = rotation_in_flange(model.body_iquat[body])
        mass_kg = float(model.body_mass[body])
        com_in_flange = position_in_flange(model.body_ipos[body])
        inertia = principal_axes @ np.diag(model.body_inertia[body]) @ principal_axes.T
    else:
        mass_kg, com_in_flange, inertia = _composite_in_flange(model, data, body, flange)
    return ToolSpec(
        mass_kg=mass_kg,
        com_in_flange=com_in_flange,
        inertia_in_flange=read_only(inertia),
        sensor_position_in_flange=position_in_flange(model.site_pos[sensor]),
        sensor_rotation_in_flange=rotation_in_flange(model.site_quat[sensor]),
        tool_position_in_flange=position_in_flange(model.site_pos[point]),
        tool_rotation_in_flange=rotation_in_flange(model.site_quat[point]),
    )


def _composite_in_flange(
    model: mujoco.MjModel, data: mujoco.MjData, root: int, flange: int
) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, centre of mass and inertia about it (flange axes) of body ``root`` and its subtree.

    Summed over the bodies at the scene's home pose by the parallel-axis theorem, from
    MuJoCo's world-frame centres (``xipos``) and principal axes (``ximat``).
    """
    bodies = [b for b in range(model.nbody) if descends(model, b, root)]
    rotation_flange = data.site_xmat[flange].reshape(3, 3)
    origin_flange = data.site_xpos[flange]
    masses = np.array([model.body_mass[b] for b in bodies])
    centres = np.array([rotation_flange.T @ (data.xipos[b] - origin_flange) for b in bodies])
    mass = float(masses.sum())
    com = masses @ centres / mass
    inertia = np.zeros((3, 3))
    for b, m, c in zip(bodies, masses, centres, strict=True):
        axes = rotation_flange.T @ data.ximat[b].reshape(3, 3)
        r = c - com
        inertia += axes @ np.diag(model.body_inertia[b]) @ axes.T + m * (r @ r * np.eye(3) - np.outer(r, r))
    return mass, read_only(com), inertia


def descends(model: mujoco.MjModel, body: int, root: int) -> bool:
    """Whether ``body`` is ``root`` or below it."""
    while body > 0:
        if body == root:
            return True
        body = int(model.body_parentid[body])
    return False


@functools.cache
def _read_fixture_frames(scene_xml: Path) -> tuple[FixtureFrame, ...]:
    return kept(scene_xml.parent, f"fixtures:{scene_xml.name}", lambda: fixture_frames_from_scene(scene_xml))


def fixture_frames_from_scene(scene_xml: Path = SCENE_XML) -> tuple[FixtureFrame, ...]:
    """The fixture frames of :data:`FIXTURE_NAMES`, read from the compiled scene's sites."""
    model, data = _scene_at_home(scene_xml)
    frames = []
    for name in FIXTURE_NAMES:
        site = _object_id(model, mujoco.mjtObj.mjOBJ_SITE, name)
        frames.append(
            FixtureFrame(
                name=name,
                position=read_only(data.site_xpos[site]),
                rotation=read_only(data.site_xmat[site].reshape(3, 3)),
            )
        )
    return tuple(frames)


def fixture_frames(robot: Robot = DEFAULT_ROBOT) -> dict[str, FixtureFrame]:
    """The workcell's predefined frames by name: ``table``, ``hole``, ``slope``.

    Read from the sites of the same names in the arm's scene (once; the arrays are read-only).
    Both arms' scenes hold the same fixtures (``tests/test_panda_model.py``).

    Returns:
        A new dict on each call, so callers may add their own entries to it.
    """
    return {frame.name: frame for frame in _read_fixture_frames(robot.scene_xml)}


HOME_Q: np.ndarray = home_q(PUMA560)
"""The PUMA's home configuration [rad], ``(6,)``, read-only: the scene's ``home`` keyframe."""

HOME_TOOL_POSITION, HOME_TOOL_ROTATION = kept(
    SCENE_XML.parent, f"home_tool:{SCENE_XML.name}", lambda: home_tool_from_scene(SCENE_XML)
)
"""Where the tool point is at home, world [m] (3,), and its orientation, tool to world (3, 3),
read from the scene (:data:`cosmos.capabilities.HOME_TOOL` states the same numbers for the
language, which may not import this module; tests/run/test_supervision_units.py compares)."""

TOOL: ToolSpec = tool_spec(PUMA560)
"""The tool mounted in the PUMA's scene, as the controller is allowed to know it (the Panda
carries the same one: ``tests/test_panda_model.py``)."""
