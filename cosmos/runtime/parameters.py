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

import numpy as np
import pinocchio as pin

from cosmos.osc.dynamics import OperationalDynamics, operational_dynamics
from cosmos.osc.force import Selection
from cosmos.osc.limits import joint_limit_torque
from cosmos.osc.unified import ForceGains, ServoMatrices, servo_matrices
from cosmos.robot_model import RobotModel
from cosmos.workcell import TOOL

FloatArray = np.ndarray


_LOWER = np.tril_indices(6, -1)
_NO_TORQUE = np.zeros(6)
_NO_TORQUE.setflags(write=False)


def _symmetric(upper: FloatArray) -> FloatArray:
    """The symmetric matrix whose upper triangle is given (np.triu costs ~20 us here)."""
    full = upper.copy()
    full[_LOWER] = upper.T[_LOWER]
    return full


@dataclass(frozen=True)
class JointLimitField:
    """The joint-limit potential of seed section 6 (FIRAS applied to joint ranges)."""

    rho_0_rad: float = 0.15
    eta: float = 0.02
    torque_cap_nm: float = 20.0


@dataclass(frozen=True)
class Evaluation:
    """One evaluation of the model at the configuration ``q`` (all arrays read-only).

    Attributes:
        q: Joint positions at the evaluation, in [rad]. # (6,)
        position: Tool point in world, in [m]. # (3,)
        rotation_tool_to_world: Tool orientation. # (3, 3)
        rotation_sensor_to_world: Orientation of the wrist sensor. # (3, 3)
        sensor_to_tool_m: Tool point minus sensor origin, world axes, in [m]. # (3,)
        sensor_to_com_m: Tool centre of mass minus sensor origin, world axes, in [m]. # (3,)
        jacobian: Tool-point Jacobian, rows ``[linear; angular]``, world axes. # (6, 6)
        inertia: Joint-space kinetic energy matrix A(q) with rotor inertia. # (6, 6)
        gravity: g(q), in [N m]. # (6,)
        dynamics: Lambda, mu, p, Jbar of eq. 27-28.
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
    gravity: FloatArray
    dynamics: OperationalDynamics
    joint_limit_torque: FloatArray


class ParameterLevel:
    """Evaluates the controller's model; one instance per runtime (it owns Pinocchio data)."""

    def __init__(self, robot: RobotModel, limit_field: JointLimitField = JointLimitField()):
        self._robot = robot
        self._model = robot.model
        self._data = robot.model.createData()
        self._limit_field = limit_field
        self._sensor_to_com_in_flange = TOOL.com_in_flange - TOOL.sensor_position_in_flange

    def _joint_limit_torque(self, q: FloatArray) -> FloatArray:
        """Section 6's joint-limit repulsion; zero (and cheap) when every joint is far from its limits."""
        robot, field = self._robot, self._limit_field
        margin = min(float((q - robot.q_lower_rad).min()), float((robot.q_upper_rad - q).min()))
        if margin >= field.rho_0_rad:
            return _NO_TORQUE
        return joint_limit_torque(
            q, robot.q_lower_rad, robot.q_upper_rad, field.rho_0_rad, field.eta, field.torque_cap_nm
        )

    def evaluate(self, q: FloatArray, qd: FloatArray) -> Evaluation:
        """Evaluate J, A, b, g, h and the operational dynamics at ``(q, qd)``."""
        model, data, robot = self._model, self._data, self._robot
        pin.computeAllTerms(model, data, q, qd)  # A (upper), nle, J, dJ, placements
        pin.updateFramePlacements(model, data)
        inertia = _symmetric(data.M)  # Pinocchio fills the upper triangle only
        inertia_inv = _symmetric(pin.computeMinverse(model, data, q))
        jacobian = pin.getFrameJacobian(model, data, robot.tool_frame, pin.LOCAL_WORLD_ALIGNED)
        jdot = pin.getFrameJacobianTimeVariation(model, data, robot.tool_frame, pin.LOCAL_WORLD_ALIGNED)
        gravity = pin.computeGeneralizedGravity(model, data, q).copy()
        bias = data.nle - gravity  # b(q, qd) of eq. 12
        dynamics = operational_dynamics(
            inertia, jacobian, bias, gravity, jdot.dot(qd), inertia_inv=inertia_inv
        )
        tool = data.oMf[robot.tool_frame]
        sensor = data.oMf[robot.sensor_frame]
        rotation_sensor = sensor.rotation.copy()
        rotation_flange = data.oMf[robot.flange_frame].rotation
        return Evaluation(
            q=q.copy(),
            position=tool.translation.copy(),
            rotation_tool_to_world=tool.rotation.copy(),
            rotation_sensor_to_world=rotation_sensor,
            sensor_to_tool_m=tool.translation - sensor.translation,
            sensor_to_com_m=rotation_flange.dot(self._sensor_to_com_in_flange),
            jacobian=jacobian,
            inertia=inertia,
            gravity=gravity,
            dynamics=dynamics,
            joint_limit_torque=self._joint_limit_torque(q),
        )


def fold_for_servo(
    evaluation: Evaluation, selection: Selection, gains: ForceGains, xi_q: float
) -> tuple[ServoMatrices, FloatArray]:
    """The servo's matrices (eq. 29) and the null-space damping matrix of eq. 34.

    Returns:
        ``(matrices, null_damping)`` where ``null_damping @ qd`` is
        ``-xi_q A (I - Jbar J) qd``. # (6, 6)
    """
    dynamics = evaluation.dynamics
    j = dynamics.jacobian
    null_damping = -xi_q * (evaluation.inertia - j.T.dot(dynamics.lambda_).dot(j))
    return servo_matrices(dynamics, selection, gains), null_damping
