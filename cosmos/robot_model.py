"""The controller's dynamic model of the arm: Pinocchio, built from the bare arm's MJCF.

The controller does not see the simulator's model. It knows the published arm
(``puma560.xml``, parsed by Pinocchio) and the tool's datasheet
(:data:`cosmos.workcell.TOOL`), which is added to link 6 here.

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
from cosmos.workcell import (
    ARM_XML,
    FLANGE_SITE,
    JOINT_NAMES,
    SENSOR_SITE,
    TOOL,
    TOOL_SITE,
    read_only,
)

GRAVITY = read_only(np.array([0.0, 0.0, -9.81]))
"""Gravity in the world (base) frame [m/s^2]."""


@dataclass(frozen=True)
class RobotModel:
    """The arm with its tool as the controller knows it.

    ``model`` and ``data`` are Pinocchio's; the arrays are read-only, ``(6,)``,
    in joint order. The frames ``flange``, ``ft_sensor`` (wrist sensor's
    measuring frame) and ``tool`` (tool point, z along the peg) are on joint 6.

    Attributes:
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
        coulomb_nm: Coulomb friction (symmetric) [N m].
    """

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


def _drive_torque_limits() -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper torque limits [N m] from the arm's motor ``ctrlrange``, joint order."""
    arm = mujoco.MjModel.from_xml_path(str(ARM_XML))
    lower, upper = np.full(len(JOINT_NAMES), -np.inf), np.full(len(JOINT_NAMES), np.inf)
    for i in range(arm.nu):
        joint = arm.joint(int(arm.actuator_trnid[i, 0])).name
        gear = float(arm.actuator_gear[i, 0])
        lower[JOINT_NAMES.index(joint)], upper[JOINT_NAMES.index(joint)] = sorted(
            gear * arm.actuator_ctrlrange[i]
        )
    return lower, upper


def build_robot_model() -> RobotModel:
    """Build the controller's model: the bare arm from its MJCF plus the tool from ``TOOL``."""
    model = pin.buildModelFromMJCF(str(ARM_XML))
    model.gravity = pin.Motion(GRAVITY, np.zeros(3))
    names = tuple(model.names[1:])
    if names != JOINT_NAMES:  # pragma: no cover - guards the shipped model file
        raise CosmosError(f"{ARM_XML}: joints {names}, expected {JOINT_NAMES}")
    flange = model.getFrameId(FLANGE_SITE)
    joint6 = model.frames[flange].parentJoint
    flange_in_joint = model.frames[flange].placement

    tool_inertia = pin.Inertia(TOOL.mass_kg, TOOL.com_in_flange, TOOL.inertia_in_flange)
    model.appendBodyToJoint(joint6, tool_inertia, flange_in_joint)
    sensor_in_flange = pin.SE3(TOOL.sensor_rotation_in_flange, TOOL.sensor_position_in_flange)
    tool_in_flange = pin.SE3(TOOL.tool_rotation_in_flange, TOOL.tool_position_in_flange)
    sensor = model.addFrame(
        pin.Frame(SENSOR_SITE, joint6, flange, flange_in_joint * sensor_in_flange, pin.OP_FRAME),
        False,
    )
    tool = model.addFrame(
        pin.Frame(TOOL_SITE, joint6, flange, flange_in_joint * tool_in_flange, pin.OP_FRAME),
        False,
    )

    tau_lower, tau_upper = _drive_torque_limits()
    model.effortLimit = np.maximum(-tau_lower, tau_upper)
    return RobotModel(
        model=model,
        data=model.createData(),
        flange_frame=flange,
        sensor_frame=sensor,
        tool_frame=tool,
        q_lower_rad=read_only(model.lowerPositionLimit),
        q_upper_rad=read_only(model.upperPositionLimit),
        tau_lower_nm=read_only(tau_lower),
        tau_upper_nm=read_only(tau_upper),
        armature_kgm2=read_only(model.armature),
        viscous_nms_per_rad=read_only(model.damping),
        coulomb_nm=read_only(model.friction),
    )
