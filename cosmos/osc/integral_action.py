"""Integral action on the translation error of the unit-mass end effector (added to seed eq. 19-21).

Eq. 19 and eq. 20-21 are a spring and a damper about the goal: a steady force the
controller's model does not hold (friction along a surface, a link heavier than
modelled) is balanced only by a steady error ``Lambda^-1 f / kp``, and a joint's static
friction then holds the arm there. These integrals add ``- k_i integral(e_p) dt`` to
F*_m where that error would otherwise stay: a slide's once its reference has stopped
(:func:`integrate_motion_error`), a free goal motion's near its goal
(:func:`integrate_goal_error`). A free hold (WAIT, and the hold under POSTURE or the
links' field moving the arm through the null space) instead observes the disturbance and
takes it off F*_m (:func:`observe_hold_disturbance`): quicker than an integral at the step
a joint's friction makes when the null space sets it turning. A COMPLY spring integrates
not its position error but its law's, ``k (x_anchor - x) - f`` (:func:`hold_spring_law`), so
that it stays the spring the program declares. The compiled servo tick
(:mod:`cosmos.runtime.kernels.servo`, :mod:`cosmos.runtime.kernels.spring`) runs the same
arithmetic.
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray


def integrate_motion_error(
    integral: FloatArray, error: FloatArray, omega_bar: FloatArray, dt_s: float, limit: float
) -> FloatArray:
    """One step of the integral action on the motion axes' translation error, in contact.

    Eq. 19 (or 20-21) with ``- k_i integral(Omega e_p) dt`` added to F*_m: along a
    surface the friction (a table's 0.3 x 30 N) is a steady force that the
    position loop alone balances only with a steady error (``f / (Lambda kp)``,
    millimetres) and that static friction then holds short of the goal. The
    integral grows until it beats the friction; each component is clamped to
    ``+-limit`` (anti-windup), and it restarts with every segment. Once the tool has
    passed its goal (error and integral pointing apart: the integral pushes it on), the
    integral's part along the error is dropped first: wound up on the lag a slide's tool
    still has when its reference stops (the friction's millimetres), the integral carried
    the tool 1.2 mm past its goal, where friction held it.

    Args:
        integral: The integral so far, world, in [m s]. # (3,)
        error: ``x - x_d``, world, in [m] then [rad]. # (6,)
        omega_bar: Force-controlled projector (its translation block is used). # (6, 6)
        dt_s: Servo period, in [s].
        limit: Clamp per component, in [m s].

    Returns:
        The new integral. # (3,)
    """
    along = error[:3] - omega_bar[:3, :3].dot(error[:3])
    past = float(along.dot(integral))
    kept = integral - (past / float(along.dot(along))) * along if past < 0.0 else integral
    return np.clip(kept + along * dt_s, -limit, limit)


def integrate_goal_error(
    integral: FloatArray,
    error: FloatArray,
    velocity: FloatArray,
    force: FloatArray,
    dt_s: float,
    gate: tuple[float, float, float, float],
) -> FloatArray:
    """One step of the integral action on a free goal motion's translation error, near its goal.

    Eq. 20-21 near the goal are ``-kp e - kv xd``: a steady force the model does not know
    (a link or a held tool a few per cent heavier than modelled, a joint's friction above
    its compensation) is balanced only by a steady error ``Lambda^-1 f / kp`` (1 mm for
    2 m/s^2 of unmodelled acceleration at kp = 400), and static friction holds the arm
    there. Adding ``- k_i integral(e_p) dt`` to F*_m removes it; the integral grows only
    where the tool is within ``band`` of its goal, slower than ``slow`` and feels no push
    over ``quiet`` (in free space: the motion's own approach, which eq. 20-21 bring in
    without overshoot, and a motion blocked by something are left as they were), is
    clamped to ``+-limit`` per component (anti-windup) and restarts with every segment.

    Args:
        integral: The integral so far, world, in [m s]. # (3,)
        error: ``x - x_d``, world, in [m] then [rad]. # (6,)
        velocity: Tool twist, world, in [m/s] then [rad/s]. # (6,)
        force: The wrench the tool applies, world, in [N] then [N m]. # (6,)
        dt_s: Servo period, in [s].
        gate: ``(limit [m s], band [m], slow [m/s], quiet [N])``.

    Returns:
        The new integral. # (3,)
    """
    limit, band, slow, quiet = gate
    near = float(np.linalg.norm(error[:3])) < band and float(np.linalg.norm(velocity[:3])) < slow
    if not (near and float(np.linalg.norm(force[:3])) < quiet):
        return np.array(integral, dtype=float)
    return np.clip(integral + np.asarray(error[:3]) * dt_s, -limit, limit)


def observe_hold_disturbance(
    estimate: FloatArray,
    predicted: FloatArray | None,
    command: FloatArray,
    velocity: FloatArray,
    error: FloatArray,
    force: FloatArray,
    dt_s: float,
    gate: tuple[float, float, float, float],
    known: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """One tick of a free hold's disturbance observer: eq. 19 (x_d fixed) less the estimated disturbance.

    With eq. 18 the decoupled tool is a unit mass, ``xdd = F*_m``; the real arm adds a
    disturbance ``d`` the model does not hold: the drawn friction levels of the joints that
    move (a null-space motion under POSTURE or the links' field turns joints 1-3 too, and
    10 % of joint 1's 25 N m is 0.4 m/s^2 at the tool, a millimetre at kp = 400), the
    masses' few per cent, and what of a null-space torque ``N^T Gamma_0`` the controller's A
    does not keep from the tool. It comes as a step when a joint starts turning, which
    integral action (:func:`integrate_goal_error`: roots -26, -10, -3.8 /s) takes back only
    after most of the step's ``d / kp``. The observer compares the velocity measured with
    the one the unit mass should have reached, ``v_pred = v + dt (F* + a_known)`` of the tick
    before (``a_known``: what the controller gives the tool on purpose besides F*, a field
    meant to reach it), ``d <- d + L (v - v_pred)``: d follows the disturbance at first
    order with time constant ``1 / L``, and ``F*_m - d`` goes to the servo. Written out,
    ``d = L (v - integral(F*) dt)``, so the hold is eq. 19 with ``kp + L kv``, ``kv + L``
    and an integral gain ``L kp``: at L = 20 /s, the hold's own double root, the three roots
    are at -20 /s (a constant disturbance is held with no steady error). d moves only
    where the tool is within ``band`` of what it holds and feels no push over ``quiet`` (a
    contact is not a disturbance to take back), is clamped to ``+-bound`` per component and
    restarts with every segment; the segment's first tick (no ``predicted`` yet) only takes
    the velocity.

    Args:
        estimate: d so far, world, in [m/s^2]. # (3,)
        predicted: v_pred for this tick, world, in [m/s]; None on a segment's first tick. # (3,)
        command: F*_m of this tick (eq. 19), world, [m/s^2] then [rad/s^2]. # (6,)
        velocity: Tool twist, world, in [m/s] then [rad/s]. # (6,)
        error: ``x - x_d``, world, in [m] then [rad]. # (6,)
        force: The wrench the tool applies, world, in [N] then [N m]. # (6,)
        dt_s: Servo period, in [s].
        gate: ``(L [1/s], bound [m/s^2], band [m], quiet [N])``.
        known: What the controller gives the tool on purpose besides F*_m (a potential field
            meant to reach it: ``J A^-1 Gamma``), world, in [m/s^2]: predicted, so left to act;
            None: nothing. # (3,)

    Returns:
        The new estimate and v_pred for the next tick, and the command with d taken off. # (3,), (3,), (6,)
    """
    gain, bound, band, quiet = gate
    estimate = np.array(estimate, dtype=float)
    near = float(np.linalg.norm(error[:3])) < band and float(np.linalg.norm(force[:3])) < quiet
    if near and predicted is not None:
        estimate = np.clip(estimate + gain * (np.asarray(velocity[:3]) - predicted), -bound, bound)
    expected = np.asarray(command[:3]) + (0.0 if known is None else np.asarray(known))
    predicted = np.asarray(velocity[:3]) + dt_s * expected
    out = np.array(command, dtype=float)
    out[:3] -= estimate
    return estimate, predicted, out


SPRING_RATE = 0.25
"""The spring law's integral gain over the axis's damping: ``k_I = kv / 4`` [1]."""
SPRING_LIMIT = (10.0, 2.0)
"""Bound on the spring law's integral, as a force [N] then a moment [N m]: the joints' friction error."""
SPRING_OBSERVER = (20.0, 2.0, 0.2)
"""A free spring's disturbance observer: its rate L [1/s]; free below a force [N] and a moment [N m]."""


def hold_spring_law(
    integral: FloatArray,
    springs: FloatArray,
    kp: FloatArray,
    kv: FloatArray,
    error: FloatArray,
    wrench: FloatArray,
    dt_s: float,
) -> tuple[FloatArray, FloatArray]:
    """One step of the integral that holds a COMPLY spring to its law, task axes (added to eq. 19-21).

    A spring axis renders ``f = k (x_anchor - x)`` with eq. 19's ``-kp e - kv (xd - xd_d)`` at
    ``kp = k / lambda``: the joints' friction error (its compensation's 10 % on the realistic
    arm, and the friction a joint keeps at rest) adds to it a force the program did not ask for,
    of the order of the spring's own at 500 N/m: a 10 mm press pressed 1.0-3.5 N for 4.7 N. An
    integral of the position error would remove it by making the axis a stiff servo. This one
    integrates the spring law's error instead, the spring's force less the wrench the tool
    applies, in unit-mass terms ``s = -kp e - f / lambda``, and adds ``k_I integral(s) dt`` to
    F*_m: at rest it leaves ``f = k (x_anchor - x)`` exactly, in contact (the press is the
    spring's) and in free space (``f = 0``: the tool at its anchor). ``k_I = kv / 4`` keeps the
    free axis ``s^3 + kv s^2 + kp s + k_I kp`` stable (it needs ``k_I < kv``), and in contact
    the error decays at ``k_I`` (5 /s for 500 N/m on 5 kg). Clamped to :data:`SPRING_LIMIT`
    (anti-windup: an impact's spike), kept while the axis stays a spring, zero elsewhere.

    Args:
        integral: ``integral(s) dt`` so far, task axes, in [m/s, rad/s]. # (6,)
        springs: ``lambda``, each spring axis's effective mass [kg, kg m^2]; 0 off the springs. # (6,)
        kp: Position gains, task axes, in [1/s^2]. # (6,)
        kv: Velocity gains, task axes, in [1/s]. # (6,)
        error: ``x - x_d`` (x_d the anchor), task axes, in [m, rad]. # (6,)
        wrench: The wrench the tool applies, task axes, in [N, N m]. # (6,)
        dt_s: Servo period, in [s].

    Returns:
        The new integral and the term added to F*_m, task axes. # (6,), (6,)
    """
    masses = np.asarray(springs, dtype=float)
    on = masses > 0.0
    safe = np.where(on, masses, 1.0)
    gain = SPRING_RATE * np.asarray(kv, dtype=float)
    bound = np.repeat(SPRING_LIMIT, 3) / (safe * gain)
    law = -np.asarray(kp) * np.asarray(error) - np.asarray(wrench) / safe
    out = np.where(on, np.clip(np.asarray(integral) + law * dt_s, -bound, bound), 0.0)
    return out, gain * out
