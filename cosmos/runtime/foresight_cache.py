"""What the checker's foresight needs of an arm and its workcell, kept in the user cache.

The foresight (:mod:`cosmos.runtime.foresight`) needs the arm's kinematics (the
controller's Pinocchio model, which :func:`cosmos.robot_model.build_robot_model` builds
from the arm's MJCF with MuJoCo's help: 0.3 s and MuJoCo's import), its home
configuration and tool pose (the scene's ``home`` keyframe), and the fixtures' solids
(the world geoms of the scene). ``cosmos check`` would pay that on every start; so the
first check (or run) on a machine computes them and keeps them in the user cache
(:mod:`cosmos.user_cache`), as :mod:`cosmos.commands.fixture_cache` keeps the fixture
frames: one JSON file per arm, named by a hash of the arm's model files, MuJoCo's and
Pinocchio's installations (:func:`cosmos.user_cache.package_stamp`) and the source of the code
that derives them. The Pinocchio model
is kept as Pinocchio's own text serialisation (``Model.saveToString``, read back by
``loadFromString``: no pickle, nothing in the file is run). Reading it back costs
Pinocchio's import and a millisecond, not MuJoCo. A file that cannot be read or written
only means computing them again. What the foresight of joint limits found for a chain of
goals is kept beside it (:func:`foreseen`), so that checking a program again does not even
import Pinocchio.
"""

from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cosmos.robots import ROBOTS, Robot
from cosmos.runtime.arm_at_home import ArmCapsule, capsules_at
from cosmos.runtime.fixture_solids import FixtureSolid, SolidShape
from cosmos.user_cache import cached_array, package_stamp, user_cache_root, write_whole

_ROOT = Path(__file__).resolve().parents[1]
DERIVING_CODE = (
    _ROOT / "robot_model.py",
    _ROOT / "workcell.py",
    _ROOT / "plant_scene.py",
    _ROOT / "robots.py",
    _ROOT / "hand" / "gripper_scene.py",
    _ROOT / "osc" / "orientation.py",
    _ROOT / "runtime" / "rotation_plan.py",
    _ROOT / "runtime" / "foresight.py",
    _ROOT / "runtime" / "reach.py",
    _ROOT / "runtime" / "arm_at_home.py",
    Path(__file__).resolve(),
)
"""The source files whose code derives what is cached (a change to them changes the file's name)."""
KEPT_CHAINS = 1000
"""Chains of goals whose foresight is kept per arm and tool (a few hundred bytes each)."""
_SHAPES = {shape.value: shape for shape in SolidShape}


@dataclass(frozen=True)
class ArmKinematics:
    """The arm as :func:`cosmos.runtime.rotation_plan.plan_rotation` needs it (the peg on its flange).

    Attributes:
        model: The controller's Pinocchio model (``RobotModel.model``).
        tool_frame: Frame id of the tool point in ``model``.
        q_lower_rad: Lower joint limits [rad], read-only. # (n,)
        q_upper_rad: Upper joint limits [rad], read-only. # (n,)
        home_q: The scene's home configuration [rad], read-only. # (n,)
    """

    model: Any
    tool_frame: int
    q_lower_rad: np.ndarray
    q_upper_rad: np.ndarray
    home_q: np.ndarray


@dataclass(frozen=True)
class Workcell:
    """The arm's workcell as the checker sees it.

    Attributes:
        home_tool_position: The tool point at home, world [m], read-only. # (3,)
        home_tool_rotation: The tool's orientation at home (tool to world), read-only. # (3, 3)
        tool_length_m: From the tool point back to the flange along the tool's axis, or to the
            tool's far end if it reaches behind the flange [m].
        tool_sections: The tool's cylinders on its axis (:class:`cosmos.runtime.goals_in_fixtures.ToolShape`):
            from and to how far back from the tool point, and radius [m], each.
        flange_in_tool: Where the flange's origin (the PUMA's wrist centre) is in the tool point's
            frame [m], read-only (:func:`cosmos.runtime.reach.beyond_reach` judges it). # (3,)
        tool_ahead_m: How far the tool reaches past the tool point along its axis [m] (the
            gripper's fingertips; 0 for the peg, whose tool point is its tip).
        solids: The fixtures' solids: the scene's world geoms that the tool can touch.
        model_text: The controller's Pinocchio model, serialised (:func:`kinematics` reads it).
        tool_frame: Frame id of the tool point in that model.
        home_q: The scene's home configuration [rad], read-only. # (n,)
        arm_at_home: Capsules inside the arm's collision geoms at home
            (:func:`cosmos.runtime.arm_at_home.inscribed`).
    """

    home_tool_position: np.ndarray
    home_tool_rotation: np.ndarray
    tool_length_m: float
    tool_sections: tuple[tuple[float, float, float], ...]
    tool_ahead_m: float
    flange_in_tool: np.ndarray
    solids: tuple[FixtureSolid, ...]
    model_text: str
    tool_frame: int
    home_q: np.ndarray
    arm_at_home: tuple[ArmCapsule, ...]


def digest(robot: Robot) -> str:
    """A hash of the arm's model files, MuJoCo's and Pinocchio's installations and the deriving code."""
    stamps = f"{robot.name}\0{package_stamp('mujoco')}\0{package_stamp('pinocchio')}"
    hashed = hashlib.sha256(stamps.encode())
    files = [p for p in sorted(robot.model_dir.rglob("*")) if p.is_file()]
    for path in (*files, *DERIVING_CODE):
        hashed.update(path.name.encode() + b"\0" + path.read_bytes())
    return hashed.hexdigest()[:32]


def _tool_geoms(model: Any, tool: int) -> list[int]:
    """The geoms of body ``tool`` and of the bodies on it (the gripper's fingers)."""
    found = []
    for geom in range(model.ngeom):
        body = int(model.geom_bodyid[geom])
        while body not in (0, tool):
            body = int(model.body_parentid[body])
        if body == tool:
            found.append(geom)
    return found


def _tool_sections(model: Any, data: Any, point: int) -> tuple[tuple[float, float, float], ...]:
    """The cylinders of the tool's body (and the bodies on it) centred on the tool's axis.

    At the home pose, in the tool point's frame (z along the tool, away from the flange): each
    as from and to how far back from the tool point, and radius [m].
    """
    import mujoco

    tool = model.body("tool").id
    origin, axes = data.site_xpos[point], data.site_xmat[point].reshape(3, 3)
    sections = []
    for geom in _tool_geoms(model, tool):
        if model.geom_type[geom] != mujoco.mjtGeom.mjGEOM_CYLINDER:
            continue
        centre = axes.T @ (data.geom_xpos[geom] - origin)
        along = axes.T @ data.geom_xmat[geom].reshape(3, 3)[:, 2]
        if np.hypot(centre[0], centre[1]) > 1e-9 or abs(abs(along[2]) - 1.0) > 1e-9:
            continue  # off the axis, or across it
        radius, half = float(model.geom_size[geom, 0]), float(model.geom_size[geom, 1])
        sections.append((-float(centre[2]) - half, -float(centre[2]) + half, radius))
    return tuple(sorted(sections))


def _tool_ahead(model: Any, data: Any, point: int) -> float:
    """How far the tool's collision geoms reach past the tool point along its axis, at home [m].

    The corners of each geom's bounding box (MuJoCo's ``geom_aabb``) in the tool point's frame,
    z along the tool: the largest z, or 0.
    """
    tool = model.body("tool").id
    origin, axis = data.site_xpos[point], data.site_xmat[point].reshape(3, 3)[:, 2]
    signs = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    ahead = 0.0
    for geom in _tool_geoms(model, tool):
        if model.geom_contype[geom] == 0 and model.geom_conaffinity[geom] == 0:
            continue
        centre, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
        corners = data.geom_xpos[geom] + (centre + signs * half) @ data.geom_xmat[geom].reshape(3, 3).T
        ahead = max(ahead, float(np.max((corners - origin) @ axis)))
    return ahead


@functools.cache
def _digest_of(robot_name: str) -> str:
    return digest(ROBOTS[robot_name])


def cache_file(robot: Robot, tool: str = "peg") -> Path:
    """Where the arm's workcell with ``tool`` (``Tool`` value) is kept."""
    return user_cache_root() / "foresight" / f"{robot.name}-{tool}-{digest(robot)}.json"


def _foreseen_file(robot_name: str, tool: str, key: bytes) -> Path:
    chain = hashlib.sha256(key).hexdigest()[:32]
    kept = f"{robot_name}-{tool}-{_digest_of(robot_name)}"
    return user_cache_root() / "foresight" / kept / f"{chain}.json"


def foreseen(robot_name: str, tool: str, key: bytes) -> list[tuple[int, str]] | None:
    """What the foresight of joint limits found for a chain of goals (``key``), if kept; else None.

    Kept per arm and workcell (a file per chain, in a directory named like the workcell's file):
    a list of (step index, message).
    """
    try:
        entries = json.loads(_foreseen_file(robot_name, tool, key).read_text(encoding="utf-8"))
        return [(int(index), str(message)) for index, message in entries]
    except (OSError, ValueError, TypeError):
        return None


def keep_foreseen(robot_name: str, tool: str, key: bytes, found: list[tuple[int, str]]) -> None:
    """Keep what the foresight found for ``key`` (a cache that cannot be written keeps nothing).

    At most :data:`KEPT_CHAINS` chains are kept per arm and tool: beyond, the oldest written go.
    """
    path = _foreseen_file(robot_name, tool, key)
    try:
        write_whole(path, json.dumps(found))
        others = [file for file in path.parent.glob("*.json") if file != path]
        others.sort(key=lambda file: file.stat().st_mtime_ns)
        for old in others[: max(0, len(others) + 1 - KEPT_CHAINS)]:
            old.unlink(missing_ok=True)
    except OSError:
        pass


def _to_json(cell: Workcell) -> str:
    return json.dumps(
        {
            "home_tool_position": cell.home_tool_position.tolist(),
            "home_tool_rotation": cell.home_tool_rotation.tolist(),
            "tool_length_m": cell.tool_length_m,
            "tool_sections": [list(section) for section in cell.tool_sections],
            "tool_ahead_m": cell.tool_ahead_m,
            "flange_in_tool": cell.flange_in_tool.tolist(),
            "solids": [
                {
                    "fixture": s.fixture,
                    "geom": s.geom,
                    "shape": s.shape.value,
                    "center": s.center.tolist(),
                    "rotation": s.rotation.tolist(),
                    "size": s.size.tolist(),
                }
                for s in cell.solids
            ],
            "model": cell.model_text,
            "tool_frame": cell.tool_frame,
            "home_q": cell.home_q.tolist(),
            "arm_at_home": [capsule.as_json() for capsule in cell.arm_at_home],
        }
    )


def _from_json(text: str) -> Workcell:
    entries = json.loads(text)
    solids = tuple(
        FixtureSolid(
            fixture=str(s["fixture"]),
            geom=str(s["geom"]),
            shape=SolidShape(s["shape"]),
            center=cached_array(s["center"], (3,)),
            rotation=cached_array(s["rotation"], (3, 3)),
            size=cached_array(s["size"], (3,)),
        )
        for s in entries["solids"]
    )
    if not isinstance(entries["model"], str) or not entries["model"]:
        raise ValueError("no model")
    return Workcell(
        home_tool_position=cached_array(entries["home_tool_position"], (3,)),
        home_tool_rotation=cached_array(entries["home_tool_rotation"], (3, 3)),
        tool_length_m=float(entries["tool_length_m"]),
        tool_sections=tuple(
            (float(start), float(end), float(radius)) for start, end, radius in entries["tool_sections"]
        ),
        tool_ahead_m=float(entries["tool_ahead_m"]),
        flange_in_tool=cached_array(entries["flange_in_tool"], (3,)),
        solids=solids,
        model_text=entries["model"],
        tool_frame=int(entries["tool_frame"]),
        home_q=cached_array(entries["home_q"]),
        arm_at_home=tuple(ArmCapsule.from_json(c) for c in entries["arm_at_home"]),
    )


def from_scene(robot: Robot, tool: str = "peg") -> Workcell:
    """The arm's workcell with ``tool`` computed from its model files (MuJoCo and Pinocchio)."""
    import mujoco

    from cosmos.hand.tool import Tool
    from cosmos.plant_scene import geom_owners
    from cosmos.robot_model import build_robot_model
    from cosmos.workcell import FIXTURE_NAMES, HOME_KEY, TOOL_SITE, home_q, scene_spec, tool_spec

    hand = Tool(tool)
    spec = scene_spec(robot.scene_xml, hand, robot.name)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, HOME_KEY))
    mujoco.mj_kinematics(model, data)
    owners = geom_owners(spec, model)
    # A fixture is called by the language's frame on it (the site ``hole`` is in ``hole_fixture``).
    called = {owners[g]: owners[g] for g in range(model.ngeom)}
    for name in FIXTURE_NAMES:
        site = model.site(name)
        frame = next((s.frame for s in spec.sites if s.name == name), None)
        while frame is not None and not frame.name:
            frame = frame.frame
        if int(site.bodyid[0]) == 0 and frame is not None:
            called[frame.name] = name
    solids = []
    for g in range(model.ngeom):
        kind = mujoco.mjtGeom(int(model.geom_type[g])).name.removeprefix("mjGEOM_").lower()
        touchable = model.geom_contype[g] != 0 or model.geom_conaffinity[g] != 0
        if int(model.geom_bodyid[g]) != 0 or not touchable or kind not in _SHAPES:
            continue
        name = model.geom(g).name or f"geom {g}"
        fixture = called[owners[g]] if owners[g] != "world" else name
        solids.append(
            FixtureSolid(
                fixture=fixture,
                geom=name,
                shape=_SHAPES[kind],
                center=cached_array(data.geom_xpos[g], (3,)),
                rotation=cached_array(data.geom_xmat[g], (3, 3)),
                size=cached_array(model.geom_size[g], (3,)),
            )
        )
    arm = build_robot_model(robot, hand)
    point = model.site(TOOL_SITE).id
    mounted = tool_spec(robot, hand)
    sections = _tool_sections(model, data, point)
    return Workcell(
        home_tool_position=cached_array(data.site_xpos[point], (3,)),
        home_tool_rotation=cached_array(data.site_xmat[point], (3, 3)),
        tool_length_m=max(
            float(np.linalg.norm(mounted.tool_position_in_flange)),
            max((end for _, end, _ in sections), default=0.0),
        ),
        tool_sections=sections,
        tool_ahead_m=_tool_ahead(model, data, point),
        flange_in_tool=cached_array(
            -mounted.tool_rotation_in_flange.T @ mounted.tool_position_in_flange, (3,)
        ),
        solids=tuple(solids),
        model_text=arm.model.saveToString(),
        tool_frame=int(arm.tool_frame),
        home_q=cached_array(home_q(robot)),
        arm_at_home=capsules_at(model, data),
    )


def load_workcell(robot_name: str, tool: str = "peg") -> Workcell:
    """The arm's workcell with ``tool``: from the cache file, else from its model files (then kept)."""
    robot = ROBOTS[robot_name]
    path = cache_file(robot, tool)
    try:
        return _from_json(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        pass
    cell = from_scene(robot, tool)
    try:
        write_whole(path, _to_json(cell))
    except OSError:
        pass  # a read-only cache: computed again next time
    return cell


workcell = functools.cache(load_workcell)
"""The arm's workcell (:func:`load_workcell`, once per process and arm)."""


@functools.cache
def kinematics(robot_name: str, tool: str = "peg") -> ArmKinematics:
    """The arm's kinematics with ``tool`` for the foresight of joint limits (Pinocchio, from the cache)."""
    import pinocchio as pin

    cell = workcell(robot_name, tool)
    model = pin.Model()
    try:
        model.loadFromString(cell.model_text)
    except RuntimeError:  # a damaged model in a file that read as JSON: built again
        model.loadFromString(from_scene(ROBOTS[robot_name], tool).model_text)
    return ArmKinematics(
        model=model,
        tool_frame=cell.tool_frame,
        q_lower_rad=cached_array(model.lowerPositionLimit),
        q_upper_rad=cached_array(model.upperPositionLimit),
        home_q=cell.home_q,
    )
