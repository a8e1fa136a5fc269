"""The parameter-evaluation level of the seed's two-level architecture (section 3).

At a lower rate than the servo, from the joint encoders only, it evaluates the
geometric model, the Jacobian and the end-effector dynamic coefficients
(Lambda, mu, p of eq. 27-28, with section 5's treatment of singular
directions) on the controller's own Pinocchio model, and folds them with the
current selection and gains into the few matrices the servo level multiplies
(eq. 29 and 34).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pinocchio as pin

from cosmos.osc.dynamics import OperationalDynamics, operational_dynamics
from cosmos.osc.limits import joint_limit_torque
from cosmos.robot_model import RobotModel
from cosmos.runtime.parameter_kernel import complete_evaluation
from cosmos.workcell import TOOL

FloatArray = np.ndarray


_NO_TORQUE = np.zeros(6)
_NO_TORQUE.setflags(write=False)


@dataclass(frozen=True)
class JointLimitField:
    """The joint-limit potential of seed section 6 (FIRAS applied to joint ranges)."""

    rho_0_rad: float = 0.15
    eta: float = 0.02
    torque_cap_nm: float = 20.0


@dataclass(frozen=True)
class Evaluation:
    """One evaluation of the model at the configuration ``q`` (treat its arrays as read-only).

    Attributes:
        q: Joint positions at the evaluation, in [rad]. # (6,)
        position: Tool point in world, in [m]. # (3,)
        rotation_tool_to_world: Tool orientation. # (3, 3)
        rotation_sensor_to_world: Orientation of the wrist sensor. # (3, 3)
        sensor_to_tool_m: Tool point minus sensor origin, world axes, in [m]. # (3,)
        sensor_to_com_m: Tool centre of mass minus sensor origin, world axes, in [m]. # (3,)
        jacobian: Tool-point Jacobian, rows ``[linear; angular]``, world axes. # (6, 6)
        inertia: Joint-space kinetic energy matrix A(q) with rotor inertia. # (6, 6)
        inertia_inv: Its inverse. # (6, 6)
        gravity: g(q), in [N m]. # (6,)
        bias: b(q, qd), Coriolis and centrifugal, in [N m]. # (6,)
        jdot_qdot: h = Jdot qd of eq. 14. # (6,)
        joint_limit_torque: Section 6's joint-limit repulsion, in [N m]. # (6,)
    """

    q: FloatArray
    position: FloatArray
    rotation_tool_to_world: FloatArray
    rotation_sensor_to_world: FloatArray
    sensor_to_tool_m: FloatArray
    sensor_to_com_m: FloatArray
    jacobian: FloatArray
    inertia: FloatArray
    inertia_inv: FloatArray
    gravity: FloatArray
    bias: FloatArray
    jdot_qdot: FloatArray
    joint_limit_torque: FloatArray

    @cached_property
    def dynamics(self) -> OperationalDynamics:
        """Lambda, mu, p, Jbar of eq. 27-28 (computed when first asked; the servo folds its own)."""
        return operational_dynamics(
            self.inertia, self.jacobian, self.bias, self.gravity, self.jdot_qdot, inertia_inv=self.inertia_inv
        )


class ParameterLevel:
    """Evaluates the controller's model; one instance per runtime (it owns Pinocchio data)."""

    def __init__(self, robot: RobotModel, limit_field: JointLimitField = JointLimitField()):
        self._robot = robot
        self._model = robot.model
        self._data = robot.model.createData()
        self._limit_field = limit_field
        self._q_lower = robot.q_lower_rad.tolist()
        self._q_upper = robot.q_upper_rad.tolist()
        # The sensor, the flange and the tool point are fixed on link 6: their offsets are
        # constant in tool axes.
        frames = robot.model.frames
        tool_in_joint = frames[robot.tool_frame].placement
        sensor_in_tool = tool_in_joint.actInv(frames[robot.sensor_frame].placement)
        flange_in_tool = tool_in_joint.actInv(frames[robot.flange_frame].placement)
        com_from_sensor_in_flange = TOOL.com_in_flange - TOOL.sensor_position_in_flange
        self._rotation_sensor_to_tool = np.ascontiguousarray(sensor_in_tool.rotation)
        self._tool_from_sensor_in_tool = -sensor_in_tool.translation
        self._com_from_sensor_in_tool = flange_in_tool.rotation.dot(com_from_sensor_in_flange)

    def _joint_limit_torque(self, q: FloatArray) -> FloatArray:
        """Section 6's joint-limit repulsion; zero (and cheap) when every joint is far from its limits."""
        field, values = self._limit_field, q.tolist()
        margin = min(
            min(map(float.__sub__, values, self._q_lower)), min(map(float.__sub__, self._q_upper, values))
        )
        if margin >= field.rho_0_rad:
            return _NO_TORQUE
        robot = self._robot
        return joint_limit_torque(
            q, robot.q_lower_rad, robot.q_upper_rad, field.rho_0_rad, field.eta, field.torque_cap_nm
        )

    def evaluate(self, q: FloatArray, qd: FloatArray) -> Evaluation:
        """Evaluate the placements, J, A, A^-1, b, g and h = Jdot qd at ``(q, qd)``."""
        model, data, frame = self._model, self._data, self._robot.tool_frame
        pin.computeAllTerms(model, data, q, qd)  # A (upper), nle, joint Jacobians, dJ, placements
        tool = pin.updateFramePlacement(model, data, frame)
        jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
        jdot = pin.getFrameJacobianTimeVariation(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
        minv = pin.computeMinverse(model, data, q)
        gravity = pin.computeGeneralizedGravity(model, data, q).copy()
        rotation_tool = np.ascontiguousarray(tool.rotation)  # Eigen is column-major; the kernels take C order
        inertia, inertia_inv, bias, jdot_qdot, rotation_sensor, sensor_to_tool, sensor_to_com = (
            complete_evaluation(
                data.M,
                minv,
                data.nle,
                gravity,
                jdot,
                qd,
                rotation_tool,
                self._rotation_sensor_to_tool,
                self._tool_from_sensor_in_tool,
                self._com_from_sensor_in_tool,
            )
        )
        return Evaluation(
            q=q.copy(),
            position=tool.translation,
            rotation_tool_to_world=rotation_tool,
            rotation_sensor_to_world=rotation_sensor,
            sensor_to_tool_m=sensor_to_tool,
            sensor_to_com_m=sensor_to_com,
            jacobian=jacobian,
            inertia=inertia,
            inertia_inv=inertia_inv,
            gravity=gravity,
            bias=bias,
            jdot_qdot=jdot_qdot,
            joint_limit_torque=self._joint_limit_torque(q),
        )
