"""The unified motion and force command (seed eq. 16-18, 29 and Figure 2).

Operational force on the end effector::

    F   = Lambda Omega F*_m + Omega_bar F_a + mu + p                       (eq. 17-18)
    F_a = F_d + k_f (F_d - F_s) + k_i integral(F_d - F_s) dt - Lambda Omega_bar k_vf xd

(near a singularity ``Lambda P Omega F*_m``, P the task projection of section 5,
:func:`cosmos.osc.dynamics.singular_task_projection`; elsewhere P = I) and the
joint torque, eq. 16 written as in eq. 29 (Appendix I, A2)::

    Gamma = J^T (Lambda Omega F*_m + Omega_bar F_a) + b + g - J^T Lambda h + N^T Gamma_0
          = J^T F + N^T (b + g + Gamma_0)

For a square, non-singular J, ``N^T = 0`` and this is exactly ``J^T F``. In a
redundant or singular case eq. 29 also compensates the null-space part of b and
g, which the end effector cannot feel, so the self-motion does not fall under
gravity; ``Gamma_0`` is any further null-space torque (eq. 34, posture).

Signs. Wrenches (force then moment, about the tool point, world axes) are:

* ``F``: what the actuators apply ON the end effector (eq. 9: ``Lambda xdd + mu
  + p = F + F_ext``, ``F_ext`` the environment's wrench on the tool).
* ``F_d`` (setpoint) and ``F_s`` (sensed): what the tool APPLIES TO THE
  ENVIRONMENT, as the language and the logs use it: ``CONTACT DOWN FORCE 10 N``
  is ``F_d = (0, 0, -10, 0, 0, 0)``. The environment pushes back with
  ``F_ext = -F_s``.

At rest in contact eq. 9 gives ``F - p = -F_ext = F_s``: the actuators' force
net of gravity equals the force the tool applies to the environment. That is
why ``F_d`` enters ``F_a`` with a plus sign (feed-forward) and the error is
``F_d - F_s``: pressing too lightly (``F_s`` short of ``F_d``) pushes harder.

Cost: the servo level (:func:`servo_torque`, one product) uses a matrix
that :func:`servo_matrices` combines once per parameter update (the seed's
two-level architecture, section 3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.osc.dynamics import OperationalDynamics
from cosmos.osc.force import Selection


@dataclass(frozen=True)
class ForceGains:
    """Gains of the force loop on force-controlled axes (Figure 2).

    Attributes:
        k_f: Proportional gain on the force error, in [1] (N per N).
        k_i: Integral gain, in [1/s] (N per N s).
        k_vf: Velocity damping of the force-controlled axes, in [1/s]; multiplied by
            Lambda it is a physical damping.
        integral_limit: Clamp on each component of the force-error integral, in [N s]
            (and [N m s]): the anti-windup bound.
    """

    k_f: float = 0.0
    k_i: float = 0.0
    k_vf: float = 0.0
    integral_limit: float = math.inf

    def __post_init__(self) -> None:
        if min(self.k_f, self.k_i, self.k_vf, self.integral_limit) < 0.0:
            raise ValueError(f"ForceGains: gains and integral_limit must be >= 0, got {self}")


def integrate_force_error(
    integral: FloatArray,
    force_setpoint: FloatArray,
    force_sensed: FloatArray,
    omega_bar: FloatArray,
    dt_s: float,
    limit: float,
) -> FloatArray:
    """One step of ``integral(Omega_bar (F_d - F_s)) dt`` with an anti-windup clamp.

    Only the force-controlled part is integrated (on motion axes the error means
    nothing and would wind up); each component is clamped to ``[-limit, limit]``.
    Reset the integral to zero when the selection changes.

    Args:
        integral: The integral so far, in [N s] and [N m s]. # (6,)
        force_setpoint: F_d, applied to the environment, in [N] and [N m]. # (6,)
        force_sensed: F_s, applied to the environment, in [N] and [N m]. # (6,)
        omega_bar: Force-controlled projector. # (6, 6)
        dt_s: Servo period, in [s].
        limit: Clamp per component, in [N s].

    Returns:
        The new integral. # (6,)
    """
    updated = integral + omega_bar.dot(force_setpoint - force_sensed) * dt_s
    return np.minimum(np.maximum(updated, -limit), limit)


REACH_FRACTION = 0.9
"""Share of its goal the push must reach before the force error is integrated."""


def force_goal_reached(force_goal: FloatArray, force_sensed: FloatArray) -> bool:
    """Whether the sensed push along the goal has reached ``REACH_FRACTION`` of it.

    The force loop's integral (:func:`integrate_force_error`) starts only then: while
    a soft contact builds up after the touch, the error is large for a few hundred
    milliseconds and its integral would overshoot the setpoint (51 % on a 10 N
    CONTACT with the elliptic friction cone); once reached, the integral removes the
    steady error as before. A zero goal counts as reached.

    Args:
        force_goal: The segment's F_d goal, applied to the environment, in [N] and [N m]. # (6,)
        force_sensed: F_s, applied to the environment, in [N] and [N m]. # (6,)

    Returns:
        True once ``F_goal . F_s >= REACH_FRACTION |F_goal|^2``.
    """
    return bool(force_goal.dot(force_sensed) >= REACH_FRACTION * force_goal.dot(force_goal))


def force_feedback(
    force_setpoint: FloatArray,
    force_sensed: FloatArray,
    force_integral: FloatArray,
    gains: ForceGains,
) -> FloatArray:
    """The part of F_a without damping: ``F_d + k_f (F_d - F_s) + k_i integral``.

    Args:
        force_setpoint: F_d, applied to the environment, in [N] and [N m]. # (6,)
        force_sensed: F_s, applied to the environment, in [N] and [N m]. # (6,)
        force_integral: From :func:`integrate_force_error`, in [N s]. # (6,)
        gains: Force loop gains.

    Returns:
        A wrench on the end effector, in [N] and [N m]. # (6,)
    """
    return (1.0 + gains.k_f) * force_setpoint - gains.k_f * force_sensed + gains.k_i * force_integral


def force_command(
    force_setpoint: FloatArray,
    force_sensed: FloatArray,
    force_integral: FloatArray,
    velocity: FloatArray,
    lambda_: FloatArray,
    omega_bar: FloatArray,
    gains: ForceGains,
) -> FloatArray:
    """F_a: setpoint fed forward, PI on the force error, damping ``-Lambda Omega_bar k_vf xd``.

    Args:
        force_setpoint: F_d, applied to the environment, in [N] and [N m]. # (6,)
        force_sensed: F_s, applied to the environment, in [N] and [N m]. # (6,)
        force_integral: From :func:`integrate_force_error`, in [N s]. # (6,)
        velocity: Tool twist xd, in [m/s] and [rad/s]. # (6,)
        lambda_: Lambda. # (6, 6)
        omega_bar: Force-controlled projector. # (6, 6)
        gains: Force loop gains.

    Returns:
        F_a, on the end effector, in [N] and [N m]; eq. 17 applies Omega_bar. # (6,)
    """
    damping = lambda_.dot(omega_bar.dot(velocity)) * gains.k_vf
    return force_feedback(force_setpoint, force_sensed, force_integral, gains) - damping


def unified_torque(
    dynamics: OperationalDynamics,
    selection: Selection,
    motion_command: FloatArray,
    force_command: FloatArray,
    null_space_torque: FloatArray | None = None,
) -> FloatArray:
    """Eq. 16, 29: ``J^T (Lambda Omega F*_m + Omega_bar F_a) + b + g - J^T Lambda h``.

    Args:
        dynamics: The operational model at this configuration.
        selection: Omega and Omega_bar in world axes.
        motion_command: F*_m, in [m/s^2] and [rad/s^2]. # (6,)
        force_command: F_a, in [N] and [N m]. # (6,)
        null_space_torque: Gamma_0, projected by N^T before it is added, in [N m]. # (n,)

    Returns:
        Gamma, in [N m]. # (n,)
    """
    operational = dynamics.lambda_.dot(dynamics.task_projection.dot(selection.omega.dot(motion_command)))
    operational += selection.omega_bar.dot(force_command)
    torque = dynamics.jacobian.T.dot(operational) + dynamics.compensation_torque
    if null_space_torque is not None:
        torque += dynamics.null_space_t.dot(null_space_torque)
    return torque


class ServoMatrices(NamedTuple):
    """Eq. 29 pre-combined for the servo level; rebuild when model, selection or gains change.

    One matrix, so the servo does a single product:
    ``Gamma = stacked @ (F*_m, F_fb, xd, 1)``.
    """

    # (n, 19): J^T Lambda P Omega | J^T Omega_bar | -k_vf J^T Omega_bar Lambda Omega_bar | bias
    stacked: FloatArray

    @property
    def motion_to_torque(self) -> FloatArray:
        """``J^T Lambda P Omega``. # (n, 6)."""
        return self.stacked[:, 0:6]

    @property
    def force_to_torque(self) -> FloatArray:
        """``J^T Omega_bar``. # (n, 6)."""
        return self.stacked[:, 6:12]

    @property
    def damping_to_torque(self) -> FloatArray:
        """``k_vf J^T Omega_bar Lambda Omega_bar`` (subtracted). # (n, 6)."""
        return -self.stacked[:, 12:18]

    @property
    def bias_torque(self) -> FloatArray:
        """``b + g - J^T Lambda h``. # (n,)."""
        return self.stacked[:, 18]


_ONE = np.ones(1)


def servo_matrices(dynamics: OperationalDynamics, selection: Selection, gains: ForceGains) -> ServoMatrices:
    """Combine the parameter-level quantities for :func:`servo_torque`.

    Args:
        dynamics: The operational model at this configuration.
        selection: Omega and Omega_bar in world axes.
        gains: Force loop gains (k_vf is folded in).

    Returns:
        The servo matrices.
    """
    j_t = dynamics.jacobian.T
    omega_bar = selection.omega_bar
    force_to_torque = j_t.dot(omega_bar)
    stacked = np.hstack(
        (
            j_t.dot(dynamics.lambda_).dot(dynamics.task_projection).dot(selection.omega),
            force_to_torque,
            -gains.k_vf * force_to_torque.dot(dynamics.lambda_).dot(omega_bar),
            dynamics.compensation_torque[:, None],
        )
    )
    return ServoMatrices(stacked)


def servo_torque(
    servo: ServoMatrices, motion_command: FloatArray, force_feedback: FloatArray, velocity: FloatArray
) -> FloatArray:
    """The same Gamma as :func:`unified_torque` (no null-space term), in one product.

    Args:
        servo: From :func:`servo_matrices`.
        motion_command: F*_m, in [m/s^2] and [rad/s^2]. # (6,)
        force_feedback: From :func:`force_feedback`, in [N] and [N m]. # (6,)
        velocity: Tool twist xd, in [m/s] and [rad/s]. # (6,)

    Returns:
        Gamma, in [N m]. # (n,)
    """
    return servo.stacked.dot(np.concatenate((motion_command, force_feedback, velocity, _ONE)))


def push_axis(force_goal: FloatArray, lambda_inv_omega_bar: FloatArray) -> tuple[FloatArray, float]:
    """A push's direction ``n = F_d / |F_d|`` (translation) and ``n^T Lambda^-1 Omega_bar n``.

    The inverse of the tool's mass along the push; ``(0, 0)`` when F_d has no force.
    """
    push = float(np.linalg.norm(force_goal[:3]))
    if push == 0.0:
        return np.zeros(3), 0.0
    n = force_goal[:3] / push
    return n, float(n.dot(lambda_inv_omega_bar[:3, :3]).dot(n))


def speed_limited_push(
    feedback: FloatArray,
    force_goal: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    lambda_inv_omega_bar: FloatArray,
    max_speed: float,
    kv: float,
    k_vf: float,
    feedforward: float = 0.0,
) -> tuple[FloatArray, bool]:
    """A force-controlled push held to its speed limit: eq. 20-21's V_max on a force axis.

    Along the push ``n = F_d / |F_d|`` (translation) the force loop commands
    ``n^T F_fb``. In free space, or when the tool breaks through (a peg dropping
    into its hole), nothing resists it and the tool accelerates until the
    damping ``k_vf Lambda xd`` balances it: 15 N on 5 kg at k_vf = 30/s is
    100 mm/s. So the push is capped by the force that moves the tool at V_max
    against what it meets, measured: the sensed push plus a unit-mass velocity
    servo toward V_max (eq. 20's ``-kv (xd - nu xd_d)`` with the speed at its
    limit), plus the damping it must overcome::

        f_speed = n^T F_s + m_n (a_r + kv (V_max - n^T xd) + k_vf n^T xd),  m_n = 1 / (n^T Lambda^-1 n)

    with ``V_max`` the push's speed reference and ``a_r`` its rate of rise
    (:mod:`cosmos.osc.push_speed`; 0 once the reference is at its aim).

    ``n^T F_fb`` is replaced by ``min(n^T F_fb, f_speed)``. Pressing at rest
    (``n^T xd = 0``) the cap is the sensed force plus ``m_n kv V_max`` above it, so
    it only binds while the force is rising faster than the contact can take.

    While it binds, the push is a velocity command along n, and the force loop of the
    compliant translations around it is dropped: their ``F_d`` is 0 (INSERT's COMPLY X Y),
    so eq. 18's ``F_d + k_f (F_d - F_s) + k_i integral`` there is ``-k_f F_s + k_i integral``,
    which adds 0.6 times the contact's own push (k_f = 0.6) and the integral's to the force
    that moves the tool away from what it touches. On a slope (a chamfer) that motion
    carries the tool down the slope, past the cap: a peg landing 2 mm off the hole's axis
    peaked at 5.25-5.65 mm/s at SPEED 5 mm/s on the ideal plant, seeds 0-4 (the cap aims
    at 4.5), while the capped push was pulling it back. Without it those axes keep eq.
    18's damping ``-Lambda Omega_bar k_vf xd`` and yield to the contact as a damped free
    body: 4.9-5.3 mm/s (tests/run/test_run_insert_speed.py); their integral is held.
    No integral action: one on the speed error (tried until 2026-11-24) wound up while
    the joints stuck below the friction compensation's ramp and overshot SPEED 5 mm/s by
    12 %; without it the push keeps slightly under its aim (27 mm at SPEED 20 mm/s in
    1.60 s instead of 1.52 s) and never over its limit.

    Args:
        feedback: F_fb from :func:`force_feedback`, world, [N, N m]. # (6,)
        force_goal: The segment's force setpoint F_d (not ramped), world. # (6,)
        force_sensed: F_s, world, [N, N m]. # (6,)
        velocity: Tool twist, world, [m/s, rad/s]. # (6,)
        lambda_inv_omega_bar: ``Lambda^-1 Omega_bar``. # (6, 6)
        max_speed: V_max (the speed reference), in [m/s].
        kv: Velocity gain of the speed servo, in [1/s].
        k_vf: The force axes' damping gain (eq. 18's F_a), in [1/s].
        feedforward: ``a_r``, the reference's rate of rise, in [m/s^2].

    Returns:
        ``(F_fb, limited)``: the capped feedback (its translation off n dropped) and whether
        the cap bound.
    """
    n, inverse_mass = push_axis(force_goal, lambda_inv_omega_bar)
    if not inverse_mass > 0.0:
        return feedback, False
    along = float(n.dot(velocity[:3]))
    servo = feedforward + kv * (max_speed - along) + k_vf * along
    allowed = float(n.dot(force_sensed[:3])) + servo / inverse_mass
    asked = float(n.dot(feedback[:3]))
    if asked <= allowed:
        return feedback, False
    capped = feedback.copy()
    capped[:3] = allowed * n
    return capped, True


def push_commanded_speed(force_goal: FloatArray, max_speed: float) -> FloatArray:
    """The speed a push held at its limit commands outright, for the friction's intent: ``V_max n``.

    While :func:`speed_limited_push` binds, the push is a velocity command, and the joints'
    Coulomb friction is compensated toward it (:func:`cosmos.osc.friction.friction_intent`'s
    ``xd_c``), as toward a tracked trajectory's ``xd_d``: from the joints' intent the force
    axes take their own sensed motion out (``-Omega_bar xd / L``), so along n the intent is
    the commanded speed alone. It was ``(V_max + n^T xd) n``, which put the sensed speed along
    n back in: on the realistic plant that speed is the 40 Hz velocity observer's, 8 ms late
    and a count's rounding (several mm/s) noisy, and the friction torque it steered (the
    published Coulomb levels, up to 27 N m) followed the noise. On the chamfer the peg then
    rang at 30-40 Hz, +-2-5 mm/s: SPEED 10 mm/s peaked at 11.7 and 12.4 mm/s (seeds 0, 2),
    now at 10.45 and 9.85 (tests/run/test_run_insert_speed.py).

    Args:
        force_goal: The segment's force setpoint F_d (not ramped), world; n is its force's direction. # (6,)
        max_speed: V_max (the speed the cap aims at), in [m/s].

    Returns:
        ``xd_c``, world, [m/s, rad/s]; zeros when F_d has no force. # (6,)
    """
    speed = np.zeros(6)
    push = float(np.linalg.norm(force_goal[:3]))
    if push > 0.0:
        speed[:3] = max_speed * force_goal[:3] / push
    return speed
