"""The controller's dynamic model of the arm: Pinocchio, built from the bare arm's MJCF.

The controller does not see the simulator's model. It knows the published arm
(:attr:`cosmos.robots.Robot.arm_xml`: ``puma560.xml`` or ``panda.xml``, parsed by
Pinocchio) and the tool's datasheet (:func:`cosmos.workcell.tool_spec`), which is
added to the last link here.

Rotor inertia: the MJCF joint ``armature`` (G^2 Jm) is parsed into
``model.armature``, and Pinocchio (>= 3; checked for 4.1 in
``tests/test_puma560_model.py``) adds it to the diagonal in ``crba``, ``rnea``
and ``aba``, as MuJoCo does in its inertia matrix. So ``crba(q)`` is the full joint-space
inertia matrix of the drives, ``M(q) = M_rigid(q) + diag(G^2 Jm)``, and nothing
is to be added by hand. Velocity terms (``nle``) and gravity do not involve it.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
import pinocchio as pin

from cosmos.errors import CosmosError
from cosmos.hand.tool import Tool
from cosmos.model_facts import kept
from cosmos.robots import DEFAULT_ROBOT, Robot
from cosmos.workcell import FLANGE_SITE, SENSOR_SITE, TOOL_SITE, ToolSpec, read_only, tool_spec

GRAVITY = read_only(np.array([0.0, 0.0, -9.81]))
"""Gravity in the world (base) frame [m/s^2]."""


@dataclass(frozen=True)
class RobotModel:
    """The arm with its tool as the controller knows it.

    ``model`` and ``data`` are Pinocchio's; the arrays are read-only, ``(n,)``,
    in joint order. The frames ``flange``, ``ft_sensor`` (wrist sensor's
    measuring frame) and ``tool`` (tool point, z along the peg) are on the last joint.

    Attributes:
        description: The arm this models (its files, joints, capabilities).
        tool: The tool's datasheet, as added to the last link.
        model: Pinocchio model: arm plus tool mass, gravity (0, 0, -9.81) m/s^2.
        data: Pinocchio workspace for ``model``.
        flange_frame: Frame id of the flange (DH frame 6).
        sensor_frame: Frame id of the wrist sensor's measuring frame.
        tool_frame: Frame id of the tool point.
        q_lower_rad: Lower joint limits [rad].
        q_upper_rad: Upper joint limits [rad].
        tau_lower_nm: Lower drive torque limits [N m].
        tau_upper_nm: Upper drive torque limits [N m].
        armature_kgm2: Rotor inertia reflected to the joints, G^2 Jm [kg m^2];
            already part of ``crba``/``rnea``/``aba`` (module docstring).
        viscous_nms_per_rad: Viscous friction, G^2 B [N m s/rad].
        coulomb_nm: Coulomb friction as the model file holds it (symmetric) [N m].
        coulomb_positive_nm: Coulomb friction while the joint turns positively [N m]: the
            published value where the arm has one (``Robot.coulomb_by_direction_nm``), else
            ``coulomb_nm``.
        coulomb_negative_nm: The same, turning negatively (a magnitude) [N m].
    """

    description: Robot
    tool: ToolSpec
    model: pin.Model
    data: pin.Data
    flange_frame: int
    sensor_frame: int
    tool_frame: int
    q_lower_rad: np.ndarray
    q_upper_rad: np.ndarray
    tau_lower_nm: np.ndarray
    tau_upper_nm: np.ndarray
    armature_kgm2: np.ndarray
    viscous_nms_per_rad: np.ndarray
    coulomb_nm: np.ndarray
    coulomb_positive_nm: np.ndarray
    coulomb_negative_nm: np.ndarray


def _drive_torque_limits(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """:func:`drive_torque_limits`, once per model (kept in the user cache: :mod:`cosmos.model_facts`)."""
    name = f"drive_limits:{robot.arm_xml.name}:{','.join(robot.joint_names)}"
    return kept(robot.arm_xml.parent, name, lambda: drive_torque_limits(robot))


def drive_torque_limits(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper torque limits [N m] from the arm's motor ``ctrlrange``, joint order."""
    arm = mujoco.MjModel.from_xml_path(str(robot.arm_xml))
    names = robot.joint_names
    lower, upper = np.full(len(names), -np.inf), np.full(len(names), np.inf)
    for i in range(arm.nu):
        joint = arm.joint(int(arm.actuator_trnid[i, 0])).name
        gear = float(arm.actuator_gear[i, 0])
        lower[names.index(joint)], upper[names.index(joint)] = sorted(gear * arm.actuator_ctrlrange[i])
    return read_only(lower), read_only(upper)


def build_robot_model(robot: Robot = DEFAULT_ROBOT, tool: Tool = Tool.PEG) -> RobotModel:
    """Build the controller's model: the bare arm from its MJCF plus its tool (:func:`tool_spec`).

    Args:
        robot: The arm.
        tool: The hand on its flange (the scene's peg, or the gripper: ``TOOL``).
    """
    model = pin.buildModelFromMJCF(str(robot.arm_xml))
    model.gravity = pin.Motion(GRAVITY, np.zeros(3))
    names = tuple(model.names[1:])
    if names != robot.joint_names:  # pragma: no cover - guards the shipped model file
        raise CosmosError(f"{robot.arm_xml}: joints {names}, expected {robot.joint_names}")
    flange = model.getFrameId(FLANGE_SITE)
    last_joint = model.frames[flange].parentJoint
    flange_in_joint = model.frames[flange].placement

    spec = tool_spec(robot, tool)
    tool_inertia = pin.Inertia(spec.mass_kg, spec.com_in_flange, spec.inertia_in_flange)
    model.appendBodyToJoint(last_joint, tool_inertia, flange_in_joint)
    sensor_in_flange = pin.SE3(spec.sensor_rotation_in_flange, spec.sensor_position_in_flange)
    tool_in_flange = pin.SE3(spec.tool_rotation_in_flange, spec.tool_position_in_flange)
    sensor = model.addFrame(
        pin.Frame(SENSOR_SITE, last_joint, flange, flange_in_joint * sensor_in_flange, pin.OP_FRAME),
        False,
    )
    tool_frame = model.addFrame(
        pin.Frame(TOOL_SITE, last_joint, flange, flange_in_joint * tool_in_flange, pin.OP_FRAME),
        False,
    )

    published = robot.coulomb_by_direction_nm
    by_direction = (
        np.column_stack((model.friction, model.friction)) if published is None else np.array(published)
    )
    tau_lower, tau_upper = _drive_torque_limits(robot)
    model.effortLimit = np.maximum(-tau_lower, tau_upper)
    return RobotModel(
        description=robot,
        tool=spec,
        model=model,
        data=model.createData(),
        flange_frame=flange,
        sensor_frame=sensor,
        tool_frame=tool_frame,
        q_lower_rad=read_only(model.lowerPositionLimit),
        q_upper_rad=read_only(model.upperPositionLimit),
        tau_lower_nm=read_only(tau_lower),
        tau_upper_nm=read_only(tau_upper),
        armature_kgm2=read_only(model.armature),
        viscous_nms_per_rad=read_only(model.damping),
        coulomb_nm=read_only(model.friction),
        coulomb_positive_nm=read_only(by_direction[:, 0]),
        coulomb_negative_nm=read_only(by_direction[:, 1]),
    )
