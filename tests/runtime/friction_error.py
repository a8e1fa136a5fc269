"""What the realistic plant's friction error does to a goal motion: a reduced model for tolerances.

The controller compensates the published viscous friction ``B qd`` and the published
Coulomb friction by direction ``c(qd) sign(qd)`` (``Tc+`` turning positively, ``|Tc-|``
negatively); the realistic arm's are ``f_v B qd`` and ``f_c c(qd) sign(qd)``
(cosmos.realism.arm_error). While the joints move, the difference is a torque
disturbance ``dtau = -(f_v - 1) B qd - (f_c - 1) c(qd) sign(qd)``,
which reaches the unit-mass task space as the acceleration ``a = J M^-1 dtau`` (Lambda^-1
J^-T = J M^-1), computed here with the controller's Pinocchio model, not the plant's.

Under eq. 21 at its speed limit the desired velocity points at the goal, so an error
``e`` across the line turns it by ``e / D`` (``D``: the distance left) and the velocity
servo pulls back with ``kv V_max e / D``: across the line the tool is the second-order
system ``e'' + kv e' + (kv V_max / D) e = a_perp`` (stiffness kp once it is within 20 mm
of the goal), weak far from the goal. :class:`LineErrorModel` integrates it along the
sensed run; along the line the speed error is ``a_along / kv``.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from cosmos.realism.arm_error import ASYMMETRY_SPEED_RAD_S
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import DEFAULT_KP

KV = 2.0 * math.sqrt(DEFAULT_KP)


def friction_disturbance(runtime: Runtime) -> np.ndarray:
    """The tool's acceleration from the friction the controller does not compensate [m/s^2]. # (3,)."""
    realism, robot = runtime.plant.realism, runtime.robot
    if realism is None:
        return np.zeros(3)
    q, qd = runtime.q.copy(), runtime.qd.copy()
    arm = realism.arm
    moving = np.minimum(np.abs(qd) / ASYMMETRY_SPEED_RAD_S, 1.0)
    viscous = (np.array(arm.viscous) - 1.0) * robot.viscous_nms_per_rad * qd
    level = np.where(qd > 0.0, robot.coulomb_positive_nm, robot.coulomb_negative_nm)
    coulomb = (np.array(arm.coulomb) - 1.0) * level * np.sign(qd) * moving
    inertia = pin.crba(robot.model, robot.data, q)
    inertia = np.triu(inertia) + np.triu(inertia, 1).T
    jacobian = pin.computeFrameJacobian(robot.model, robot.data, q, robot.tool_frame, pin.LOCAL_WORLD_ALIGNED)
    return jacobian[:3] @ np.linalg.solve(inertia, -viscous - coulomb)


class LineErrorModel:
    """The reduced model of the module docstring, stepped along a run (one :meth:`step` a tick).

    Args:
        start: The tool's start [m]. # (3,)
        goal: The goal [m]. # (3,)
        max_speed: V_max [m/s].
        dt_s: The servo period [s].
    """

    def __init__(self, start: np.ndarray, goal: np.ndarray, max_speed: float, dt_s: float):
        self.start, self.goal, self.max_speed, self.dt_s = start, goal, max_speed, dt_s
        self.direction = (goal - start) / np.linalg.norm(goal - start)
        self.error = np.zeros(3)
        self.rate = np.zeros(3)
        self.largest_error_m = 0.0
        """The largest error across the line so far [m]."""
        self.largest_speed_error_m_s = 0.0
        """The largest ``|a_along| / kv`` in the cruise (60 mm from either end) so far [m/s]."""

    def step(self, runtime: Runtime, tool: np.ndarray) -> None:
        """Advance by one tick, the run's friction disturbance at its sensed state; ``tool`` [m]."""
        acceleration = friction_disturbance(runtime)
        along = float(acceleration @ self.direction)
        across = acceleration - along * self.direction
        left = float(np.linalg.norm(self.goal - tool))
        stiffness = KV * self.max_speed / left if left > 0.02 else DEFAULT_KP
        self.rate = self.rate + self.dt_s * (across - KV * self.rate - stiffness * self.error)
        self.error = self.error + self.dt_s * self.rate
        self.largest_error_m = max(self.largest_error_m, float(np.linalg.norm(self.error)))
        travelled = float((tool - self.start) @ self.direction)
        if 0.06 < travelled < float(np.linalg.norm(self.goal - self.start)) - 0.06:
            self.largest_speed_error_m_s = max(self.largest_speed_error_m_s, abs(along) / KV)
