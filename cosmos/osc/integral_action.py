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
a joint's friction makes when the null space sets it turning. A COMPLY spring observes its
disturbance with the wrench it applies in the model (:func:`observe_spring_disturbance`), so
that it stays the spring the program declares, and the joints' Coulomb friction is compensated
toward the motion that spring model predicts, not toward its pull (:func:`spring_intent`). The
compiled servo tick
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
    reach_m: float = float("inf"),
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

    Near means within ``band`` and within ``reach_m``, where eq. 21's speed limit lets go
    (``V_max kv / kp``): its linear approach. Within ``band`` alone, a slow MOVE's cruise (2 mm/s
    among obstacles, eq. 20-21 there) wound the integral up over its last 3 mm; past the goal the
    tool ran faster than ``slow``, which froze it pushing on, and it carried the tool 44 mm
    beyond its goal at 23 mm/s.

    Args:
        integral: The integral so far, world, in [m s]. # (3,)
        error: ``x - x_d``, world, in [m] then [rad]. # (6,)
        velocity: Tool twist, world, in [m/s] then [rad/s]. # (6,)
        force: The wrench the tool applies, world, in [N] then [N m]. # (6,)
        dt_s: Servo period, in [s].
        gate: ``(limit [m s], band [m], slow [m/s], quiet [N])``.
        reach_m: ``V_max kv / kp``, in [m] (eq. 21's ``nu = 1`` within it).

    Returns:
        The new integral. # (3,)
    """
    limit, band, slow, quiet = gate
    near = float(np.linalg.norm(error[:3])) < min(band, reach_m)
    near = near and float(np.linalg.norm(velocity[:3])) < slow
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


SPRING_OBSERVER = (20.0, 10.0, 2.0)
"""A spring's disturbance observer: its rate L [1/s], and its bound as a force [N] then a moment
[N m] (the joints' friction error, and the friction compensated toward a press at rest)."""


def observe_spring_disturbance(
    estimate: FloatArray,
    predicted: FloatArray,
    springs: FloatArray,
    command: FloatArray,
    velocity: FloatArray,
    wrench: FloatArray,
    dt_s: float,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """One tick of the observer that holds a COMPLY spring to its law, task axes (added to eq. 19-21).

    A spring axis renders ``f = k (x_anchor - x)`` as eq. 19's ``-kp e - kv (xd - xd_d)`` with
    ``kp = k / lambda`` on a unit mass (eq. 18). The real arm adds a disturbance ``d``: the
    joints' friction error (a 10 % error of the compensation, and at rest against a surface the
    compensation's own push toward the spring's pull, which the surface takes): a 500 N/m spring
    10 mm short of its anchor pressed 1.0-3.5 N on the realistic arm and 10.6 N with the
    compensation toward its pull, for 5 N, and its tool stuck 0.4 s, then ran at 188 % of its
    SPEED. An integral of the position error would take d out by making the axis a stiff servo.
    Here the wrench the tool applies is part of the model: the unit mass moves as
    ``xdd = F*_m - f / lambda + d``, and ``d`` is observed from the velocity that model
    predicts, ``d <- d + L (xd - xd_pred)``, ``xd_pred = xd + dt (F*_m - f / lambda)`` of the tick
    before, and taken off F*_m (as a free hold's :func:`observe_hold_disturbance`, without its
    gate: a contact is no disturbance here, it is measured). Free, the tool then moves as the
    spring on the ideal unit mass; at rest in contact ``f = k (x_anchor - x)`` exactly (what a
    joint's static friction holds is a disturbance too). ``d`` follows at first order at
    ``L`` (20 /s), is clamped to :data:`SPRING_OBSERVER`'s bound over ``lambda`` and kept while the
    axis stays a spring (a press and the WAIT after it), zero elsewhere.

    Args:
        estimate: d so far, task axes, in [m/s^2, rad/s^2]. # (6,)
        predicted: xd_pred for this tick, task axes, in [m/s, rad/s]. # (6,)
        springs: ``lambda``, each spring axis's effective mass [kg, kg m^2]; 0 off the springs. # (6,)
        command: F*_m of this tick, task axes. # (6,)
        velocity: Tool twist, task axes. # (6,)
        wrench: The wrench the tool applies, task axes, in [N, N m]. # (6,)
        dt_s: Servo period, in [s].

    Returns:
        The new estimate and xd_pred, and the command with d taken off the spring axes. # (6,) x 3
    """
    rate, force_limit, moment_limit = SPRING_OBSERVER
    masses = np.asarray(springs, dtype=float)
    on = masses > 0.0
    safe = np.where(on, masses, 1.0)
    bound = np.repeat((force_limit, moment_limit), 3) / safe
    velocity = np.asarray(velocity, dtype=float)
    new = np.clip(np.asarray(estimate) + rate * (velocity - np.asarray(predicted)), -bound, bound)
    new_predicted = velocity + dt_s * (np.asarray(command) - np.asarray(wrench) / safe)
    out = np.array(command, dtype=float) - np.where(on, new, 0.0)
    return np.where(on, new, 0.0), np.where(on, new_predicted, 0.0), out


def spring_intent(acceleration: FloatArray, springs: FloatArray, wrench: FloatArray) -> FloatArray:
    """The acceleration the joints' Coulomb compensation turns them toward on COMPLY springs, task axes.

    The compensation (:func:`cosmos.osc.friction.friction_intent`) pushes each joint toward the
    motion it is told to make, ``Jbar L a``. On a spring axis ``a`` is the spring's pull, which at
    rest against a surface makes no motion: the surface takes the compensation's push as well. On
    the PUMA, 31.6 mm short of a 500 N/m spring's anchor (15.8 N), joint 2's compensation pushed
    14.6 N more into the table, beyond what :func:`observe_spring_disturbance` takes back (its
    10 N), and the gripper pressed 22.1 N (MuJoCo's contact force 22.2 N; 24.6 N on the ideal
    plant). The motion the spring makes is that of its model, the unit mass ``xdd = F*_m - f /
    lambda`` (eq. 18 with the wrench the tool applies): free, the pull (the compensation breaks
    the joints' static friction as before); at rest in contact, nothing more than the observed
    disturbance, which the compensation then answers, not the press.

    Args:
        acceleration: The commanded acceleration (F*_m and the commanded speed over the look-ahead),
            task axes, [m/s^2, rad/s^2]. # (6,)
        springs: ``lambda``, each spring axis's effective mass [kg, kg m^2]; 0 off the springs. # (6,)
        wrench: The wrench the tool applies, task axes, in [N, N m]. # (6,)

    Returns:
        ``a - f / lambda`` on the spring axes, ``a`` elsewhere. # (6,)
    """
    masses = np.asarray(springs, dtype=float)
    on = masses > 0.0
    pushed = np.where(on, np.asarray(wrench) / np.where(on, masses, 1.0), 0.0)
    return np.asarray(acceleration, dtype=float) - pushed
