"""The parameter-evaluation level of the seed's two-level architecture (section 3).

At a lower rate than the servo, from the joint encoders only, it evaluates the
geometric model, the Jacobian and the end-effector dynamic coefficients
(Lambda, mu, p of eq. 27-28, with section 5's treatment of singular
directions) on the controller's own Pinocchio model, and folds them with the
current selection and gains into the few matrices the servo level multiplies
(eq. 29 and 34).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pinocchio as pin

from cosmos.osc.dynamics import OperationalDynamics, kinetic_energy_matrix, operational_dynamics
from cosmos.osc.limits import joint_limit_torque
from cosmos.robot_model import RobotModel
from cosmos.runtime.kernels import evaluation as ek

FloatArray = np.ndarray


@dataclass(frozen=True)
class JointLimitField:
    """The joint-limit potential of seed section 6 (FIRAS applied to joint ranges)."""

    rho_0_rad: float = 0.15
    eta: float = 0.02
    torque_cap_nm: float = 20.0


class _Slot:
    """A read-only view of an evaluation's packed values: ``shape(n)`` values from ``offset(n)``.

    ``n`` is the arm's number of joints (:attr:`Evaluation.dof`).
    """

    def __init__(self, offset: Callable[[int], int] | int, shape: Callable[[int], tuple[int, ...]]):
        self.offset = offset if callable(offset) else (lambda n, at=offset: at)
        self.shape = shape

    def __get__(self, evaluation: Evaluation, owner: type | None = None) -> FloatArray:
        n = evaluation.dof
        start, shape = self.offset(n), self.shape(n)
        return evaluation.values[start : start + math.prod(shape)].reshape(shape)  # not np.prod's 3 us


def _fixed(*shape: int) -> Callable[[int], tuple[int, ...]]:
    return lambda n: shape


@dataclass(frozen=True)
class Evaluation:
    """One evaluation of the model at the configuration ``q``: read-only arrays, views of ``values``.

    Attributes:
        values: Everything below, packed (layout: :mod:`cosmos.runtime.kernels.evaluation`).
        joint_limit_torque: Section 6's joint-limit repulsion, in [N m]. # (n,)
        q: Joint positions at the evaluation, in [rad]. # (n,)
        position: Tool point in world, in [m]. # (3,)
        rotation_tool_to_world: Tool orientation. # (3, 3)
        rotation_sensor_to_world: Orientation of the wrist sensor. # (3, 3)
        sensor_to_tool_m: Tool point minus sensor origin, world axes, in [m]. # (3,)
        sensor_to_com_m: Tool centre of mass minus sensor origin, world axes, in [m]. # (3,)
        jacobian: Tool-point Jacobian, rows ``[linear; angular]``, world axes. # (6, n)
        inertia: Joint-space kinetic energy matrix A(q) with rotor inertia. # (n, n)
        inertia_inv: Its inverse. # (n, n)
        gravity: g(q), in [N m]. # (n,)
        bias: b(q, qd), Coriolis and centrifugal, in [N m]. # (n,)
        jdot_qdot: h = Jdot qd of eq. 14. # (6,)
    """

    values: FloatArray
    joint_limit_torque: FloatArray

    @property
    def dof(self) -> int:
        """The arm's number of joints n (the joint-limit torque has one entry per joint)."""
        return int(self.joint_limit_torque.shape[0])

    q = _Slot(ek.Q, lambda n: (n,))
    position = _Slot(ek.POSITION, _fixed(3))
    rotation_tool_to_world = _Slot(ek.ROTATION_TOOL, _fixed(3, 3))
    rotation_sensor_to_world = _Slot(ek.ROTATION_SENSOR, _fixed(3, 3))
    sensor_to_tool_m = _Slot(ek.SENSOR_TO_TOOL, _fixed(3))
    sensor_to_com_m = _Slot(ek.SENSOR_TO_COM, _fixed(3))
    jacobian = _Slot(ek.jacobian_at, lambda n: (6, n))
    inertia = _Slot(ek.inertia_at, lambda n: (n, n))
    inertia_inv = _Slot(ek.inertia_inv_at, lambda n: (n, n))
    gravity = _Slot(ek.gravity_at, lambda n: (n,))
    bias = _Slot(ek.bias_at, lambda n: (n,))
    jdot_qdot = _Slot(ek.JDOT_QDOT, _fixed(6))

    @cached_property
    def lambda_(self) -> FloatArray:
        """:attr:`dynamics`' Lambda alone: what a segment's start reads (effective masses, a landing).

        The rest of :attr:`dynamics` (Jbar, mu, p, N^T, the task projection) is the servo's, which
        folds its own: Lambda alone costs 8 us warm (the whole, 18 us), 61-63 us a segment's start
        in the executor's cold caches (73-91 us). # (6, 6)
        """
        jacobian = self.jacobian
        return kinetic_energy_matrix(jacobian.dot(self.inertia_inv.dot(jacobian.T)))[0]

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
        data = self._data = robot.model.createData()
        self.limit_field = limit_field
        self.field_ranges = (robot.q_lower_rad, robot.q_upper_rad)
        """The joint ranges the joint-limit field repels from: the arm's, or as a goal widens them
        (:func:`cosmos.runtime.rotation_plan.ranges_for_goal`), [rad]. # 2 x (n,)"""
        # The sensor, the flange and the tool point are fixed on the last link: their offsets are
        # constant in tool axes.
        frames = robot.model.frames
        tool = frames[robot.tool_frame]
        tool_in_joint = tool.placement
        sensor_in_tool = tool_in_joint.actInv(frames[robot.sensor_frame].placement)
        flange_in_tool = tool_in_joint.actInv(frames[robot.flange_frame].placement)
        com_from_sensor_in_flange = robot.tool.com_in_flange - robot.tool.sensor_position_in_flange
        n = robot.model.nv
        self._no_torque = np.zeros(n)
        self._no_torque.setflags(write=False)
        constants = np.empty(ek.C_Q_LOWER + 2 * n)
        constants[ek.C_ROTATION_TOOL_IN_JOINT : ek.C_TOOL_IN_JOINT] = tool_in_joint.rotation.ravel()
        constants[ek.C_TOOL_IN_JOINT : ek.C_ROTATION_SENSOR_TO_TOOL] = tool_in_joint.translation
        constants[ek.C_ROTATION_SENSOR_TO_TOOL : ek.C_TOOL_FROM_SENSOR] = sensor_in_tool.rotation.ravel()
        constants[ek.C_TOOL_FROM_SENSOR : ek.C_COM_FROM_SENSOR] = -sensor_in_tool.translation
        constants[ek.C_COM_FROM_SENSOR : ek.C_WEIGHT] = flange_in_tool.rotation.dot(com_from_sensor_in_flange)
        constants[ek.C_WEIGHT : ek.C_Q_LOWER] = -sum(inertia.mass for inertia in robot.model.inertias) * (
            robot.model.gravity.linear
        )
        constants[ek.C_Q_LOWER : ek.C_Q_LOWER + n] = robot.q_lower_rad
        constants[ek.C_Q_LOWER + n :] = robot.q_upper_rad
        self._constants = constants
        # computeAllTerms writes into these arrays in place: held as views, not fetched per call.
        joint = data.oMi[tool.parentJoint]
        self._views = (data.M, data.nle, data.J, data.dJ, data.Jcom, joint.rotation, joint.translation)

    def _joint_limit_torque(self, q: FloatArray, margin_rad: float) -> FloatArray:
        """Section 6's joint-limit repulsion; zero (and cheap) when every joint is far from its limits."""
        field = self.limit_field
        if margin_rad >= field.rho_0_rad:
            return self._no_torque
        lower, upper = self.field_ranges
        return joint_limit_torque(q, lower, upper, field.rho_0_rad, field.eta, field.torque_cap_nm)

    def evaluate(self, q: FloatArray, qd: FloatArray) -> Evaluation:
        """Evaluate the placements, J, A, A^-1, b, g and h = Jdot qd at ``(q, qd)``."""
        pin.computeAllTerms(self._model, self._data, q, qd)  # A (upper), nle, J, dJ, Jcom, placements
        values = ek.evaluation_values(q, qd, *self._views, self._constants)
        values.flags.writeable = False
        return Evaluation(values, self._joint_limit_torque(q, values[ek.LIMIT_MARGIN]))
