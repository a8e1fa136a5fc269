"""Integral action on a goal motion's cruise speed (eq. 20-21's velocity loop made PI).

Eq. 20 is a velocity servo, ``F*_m = -kv (xd - nu xd_d)``: once eq. 21's limit binds
(``nu < 1``) it commands the unit mass toward ``V_max`` along the line to the goal with
a proportional gain alone. A steady force the controller's model does not hold (a
joint's friction above or below its compensation, a link heavier than modelled) is then
balanced only by a steady speed error ``Lambda^-1 f / kv``: on the realistic plant a
MOVE at SPEED 10 mm/s cruised at 6.7-17.8 mm/s across seeds (0.3 m/s^2 of unmodelled
acceleration is 7.5 mm/s at kv = 40).

Here the cruise's velocity loop gets an integral along the line ``u`` from the motion's
start to its goal::

    F*_m = -kv (xd - nu xd_d) + a u,    a = k_c integral (v_m - u . xd) dt,
    dv_m/dt = kv (V_max - v_m)

``v_m`` is the ideal unit mass's response to eq. 20 at the limit (ramped,
:func:`cosmos.osc.motion.ramped_speed_limit`): the integral sees only what the model does
not explain, so the motion's own start winds nothing up (integrating ``V_max - u . xd``
carried a 100 mm/s MOVE to 115 mm/s), and the ideal plant runs as before. Steadily
``v_m = V_max`` and the tool cruises at it.

Anti-windup: ``a`` grows only while the limit binds, the tool moves along the line faster
than ``moving`` times the limit, and no push over ``quiet`` is felt; it is clamped to
``+-limit`` (an acceleration, [m/s^2]) and restarts with every segment. A tool stalled or
blocked leaves a pushing ``a`` as it is and lets a holding-back one go (frozen, it held a
5 mm/s MOVE still). ``v_m`` meanwhile runs on and, where it is more than ``moving`` times
the limit above the tool's speed, is drawn down toward it at ``kp / kv``: from rest it is
the start's own response, a lasting stall does not wind the integral up once the tool
moves again, and the sensed speed's dips below the gate (one encoder count, at 5 mm/s) do
not drag it down (clamped to the tool's speed plus the gate, it held a 5 mm/s MOVE to
3.15 mm/s). Faster than :data:`BREAKAWAY_MPS`, a disturbance that holds the tool under
``moving`` times its SPEED is taken for a block (steadily: ``d > (1 - moving) kv V_max``).

Breakaway: at a SPEED of :data:`BREAKAWAY_MPS` or less, a tool stalled at rest (neither moving
on at ``moving`` times the limit nor carried back faster) with no push over ``quiet`` grows a
pushing ``a`` by ``k_c (v_m - u . xd)``, up to ``limit``: eq. 20 from rest pulls with ``kv V``
alone (0.12 m/s^2 at 3 mm/s), and where the joints' static friction the model does not hold is
more, nothing broke it: the gripper's slow CONTACT never moved ("found no contact"; seeds 0-5 at
3 mm/s on the realistic plant). Once the tool moves, ``a`` learns the kinetic friction as above.
A slow MOVE tracks a reference instead (eq. 19, :func:`cosmos.execution.resolve.tracks_a_reference`),
but a CONTACT's approach keeps eq. 20-21, so that its landing (eq. 20's motion braked from the
first push, :func:`cosmos.osc.contact.touch_braking`, and the grid it was measured on) stays as
it was: a reference runs on into the surface until the touch, and presses its lead there with
``Lambda kp`` (16 N/mm at kp = 400 /s^2 and 40 kg). The breakaway runs up to the touch (under 2 N): at
rest on the table at 1.6 N, short of the touch, static friction held the gripper too, and with
the breakaway stopped at the braking's 0.5 N it stayed there until its TIMEOUT. The landing's
peak stays under the bar (docs/language.md, CONTACT): at the touch the hold takes over and the
integral restarts.

Once the limit no longer binds (the approach, ``nu = 1``) ``a`` bleeds out at eq. 20-21's
own approach rate ``kp / kv``, leaving the goal to eq. 20-21 and the integral near the
goal (:func:`cosmos.osc.integral_action.integrate_goal_error`). Without a line (none, or
while an obstacle's field pushes the tool off it: :func:`cosmos.runtime.goal_line.kept_line`)
it neither grows nor acts, so the field is not fought. ``k_c = kv^2 / 4`` (400 /s^2 at
kv = 40, ``ServoGains.cruise_integral``) puts the loop ``s^2 + kv s + k_c`` at a double
root ``-kv / 2`` (-20 /s): a steady error goes within about 0.2 s, without overshoot.

While it cruises, the Coulomb compensation's intent is the desired motion's (twice, less the
sensed: :func:`cruise_intent`), not the sensed speed alone, as a tracked trajectory's and a held
push's are. With the sensed speed alone, the compensation
ramps up with the joints' speeds over their first 0.01 rad/s: a negative damping, there
stronger than ``kv Lambda``, that made the tool stick-slip between 3 and 14 mm/s once the
integral held it to 10 mm/s. Friction feedforward alone was not the fix: it compensates
only the modelled friction, and the speed error is what the model gets wrong.

An INSERT's approach keeps eq. 20-21 as they were (``ServoSetpoint.cruise_integral``):
landing on the chamfer at its SPEED rather than below it, the insertion rang past its cap.

A MOVE through VIA points is one goal motion whose goal moves on at each via point: the
integral carries over onto the next leg (:func:`next_leg`), where restarting it from zero left
the new leg to the unmodelled force until the integral had learnt it again (SPEED 20 mm/s: 24.9
mm/s over 20 ms after a 45 deg turn, realistic plant, seed 0).

Below eq. 20-21's SPEEDs a MOVE tracks a reference instead
(:func:`cosmos.execution.resolve.tracks_a_reference`), and the Coulomb intent reads that
reference (:func:`tracked_intent`).

The compiled servo tick runs the same arithmetic
(:func:`cosmos.runtime.kernels.cruise.cruise_into`, :func:`cosmos.runtime.kernels.cruise.reference_speed`).
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray

BREAKAWAY_MPS = 0.0100001
"""At or below this SPEED a stalled cruise's integral grows from rest [m/s]. From rest eq. 20 pulls
the unit mass with ``kv V`` alone (0.2 m/s^2 at 5 mm/s, kv = 40: some 8 N along the PUMA's
approach), less than the joints' static friction the model does not hold: the gripper's CONTACT
DOWN from rest stood still on the realistic plant at 3 mm/s on seeds 0-5, at 5 mm/s on 0 and 2-5,
at 8 mm/s on 0, 2, 4 and 5, at 10 mm/s on none.
Faster, ``kv V`` breaks it, and a motion started just after another's stop, still settling, would
only be pushed on (a MOVE at 20 mm/s after a stopped lift ran 10.7 mm/s 9 ms in)."""


def speed_limit_binds(
    error: FloatArray, kp: FloatArray, kv: FloatArray, max_speed: float, line: FloatArray
) -> bool:
    """Eq. 21's ``nu < 1`` for the translation, ``|(kp / kv) (x_d - x)| > V_max``, the goal ahead.

    Only while the goal is still ahead along the line (``u . (x_d - x) > 0``): a tool carried
    past its goal (a wound integral let go by the bore a peg left, on a heavier arm than
    modelled) is far from it again, and cruising on there ran it 38 mm past a MOVE BY's goal
    at its SPEED, the integral holding it against eq. 20-21's pull back.

    Args:
        error: ``x - x_d``, in [m] then [rad]. # (6,)
        kp: Position gains, in [1/s^2]; the translation's smallest ratio is used. # (6,)
        kv: Velocity gains, in [1/s]. # (6,)
        max_speed: V_max now (ramped), in [m/s].
        line: Unit line from the motion's start to its goal, world (zeros: none). # (3,)
    """
    ratio = float(np.min(np.asarray(kp[:3]) / np.asarray(kv[:3])))
    ahead = float(np.dot(error[:3], line)) < 0.0
    return ahead and ratio * float(np.linalg.norm(error[:3])) > max_speed


def cruise_integral_step(
    cruise: tuple[float, float],
    line: FloatArray,
    velocity: FloatArray,
    force: FloatArray,
    max_speed: float,
    binds: bool,
    rates: tuple[float, float],
    dt_s: float,
    gate: tuple[float, float, float, float],
    breakaway: bool = True,
) -> tuple[float, float]:
    """One step of the cruise's integral ``a`` and model speed ``v_m`` (module docstring).

    Args:
        cruise: ``(a [m/s^2], v_m [m/s])`` so far.
        line: Unit line from the motion's start to its goal, world (zeros: none). # (3,)
        velocity: Tool twist, world, in [m/s] then [rad/s]. # (6,)
        force: The wrench the tool applies, world, in [N] then [N m]. # (6,)
        max_speed: V_max now (ramped), in [m/s].
        binds: Whether eq. 21's limit binds (:func:`speed_limit_binds`).
        rates: ``(kv, kp / kv)``: the model's rate and the bleed's, in [1/s].
        dt_s: Servo period, in [s].
        gate: ``(k_c [1/s^2], limit [m/s^2], moving [1], quiet [N])``.
        breakaway: Whether a tool at rest with nothing pushing back grows ``a`` (:func:`breaks_away`).

    Returns:
        The new ``(a, v_m)``.
    """
    k_c, limit, moving, quiet = gate
    integral, model = cruise
    if not np.any(line):
        return integral, model
    along = float(np.dot(velocity[:3], line))
    quiet_enough = float(np.linalg.norm(force[:3])) < quiet
    if not binds:
        return integral * max(0.0, 1.0 - rates[1] * dt_s), along
    if along > moving * max_speed and quiet_enough:
        integral = float(np.clip(integral + k_c * (model - along) * dt_s, -limit, limit))
        return integral, model + rates[0] * (max_speed - model) * dt_s
    if integral < 0.0 and quiet_enough:
        integral = min(integral + k_c * (max_speed - along) * dt_s, 0.0)
    elif breakaway and quiet_enough and along > -moving * max_speed:  # at rest, nothing pushing back
        integral = min(integral + k_c * max(model - along, 0.0) * dt_s, limit)
    model += rates[0] * (max_speed - model) * dt_s
    floor = along + moving * max_speed
    return integral, model + rates[1] * (floor - model) * dt_s if model > floor else model


def breaks_away(speed_mps: float) -> bool:
    """Whether a goal motion at ``speed_mps`` breaks a stall from rest (:data:`BREAKAWAY_MPS`)."""
    return speed_mps <= BREAKAWAY_MPS


def cruise_intent(
    binds: bool, line: FloatArray, velocity: FloatArray, command: FloatArray, kv: float, turns: bool
) -> FloatArray:
    """The operational speed added to the Coulomb intent while the limit binds: ``2 v_d - xd``. # (6,).

    ``v_d`` is eq. 21's desired velocity (``nu xd_d``, kept on its line), read off eq. 20's
    command before the integral's term: ``F*_m = kv (v_d - xd)``. The intent is then
    ``qd + Jbar (2 v_d - xd) + L Jbar F*_m``, which is ``2 qd_d - L kv (qd - qd_d)`` with
    ``qd_d = Jbar v_d``: the desired motion's joint speeds, twice, and a compensation that falls
    as a joint runs ahead of them, damping it (:func:`tracked_intent` is the same for a tracked
    reference). With ``max(V_max - u . xd, 0) u`` instead (the SPEED along the line, the sensed
    speed across it) a joint turning slowly across the line read its own sensed speed within the
    compensation's ramp, a negative damping: at SPEED 20 mm/s along -X (realistic plant, seed 0)
    joint 1 cycled between 0.005 and 0.022 rad/s at 6 Hz and the tool between 0.98 and 1.10 times
    its SPEED. The rotation likewise (``w_d`` keeps the orientation), where the task holds it with
    every rotation motion-controlled (``turns``): the wrist's joints turn slowly to keep it, and
    with the translation's intent alone joint 5 stuck at 0.004 rad/s while the integral wound up
    to 0.73 m/s^2, then broke away and ran the tool at 1.64 times its SPEED (seed 3). Zeros while
    the limit does not bind or without a line.

    Args:
        binds: Whether eq. 21's limit binds (:func:`speed_limit_binds`).
        line: The goal line, world (zeros: none). # (3,)
        velocity: The sensed twist ``xd``, world, in [m/s] then [rad/s]. # (6,)
        command: Eq. 20's ``F*_m``, world, before the integral's ``a u``, in [m/s^2]. # (6,)
        kv: The velocity gain, in [1/s].
        turns: Whether the rotation gets it too (else zeros there).

    Returns:
        In [m/s] then [rad/s], world. # (6,)
    """
    intent = np.zeros(6)
    if not binds or not np.any(line):
        return intent
    rows = 6 if turns else 3
    intent[:rows] = (
        np.asarray(velocity[:rows], dtype=float) + 2.0 * np.asarray(command[:rows], dtype=float) / kv
    )
    return intent


def cruise_command(integral: float, line: FloatArray) -> FloatArray:
    """The term ``a u`` added to F*_m, in [m/s^2]. # (6,)."""
    return np.concatenate((integral * np.asarray(line, dtype=float), np.zeros(3)))


def tracked_intent(
    command: FloatArray, velocity: FloatArray, reference_velocity: FloatArray, lookahead_s: float
) -> FloatArray:
    """What the Coulomb intent reads of a slow MOVE's tracked reference: ``F*_m + (2 xd_d - xd) / L``. # (6,).

    A MOVE at a low SPEED tracks a reference along its line with eq. 19
    (:func:`cosmos.execution.resolve.tracks_a_reference`). The friction's intent is
    ``qd + L Jbar a`` (:mod:`cosmos.osc.friction`); a trajectory's ``a`` is
    ``F*_m + xd_d / L``, so, with ``F*_m = -kp e - kv (xd - xd_d)`` and ``Jbar J = 1``, the
    intent is ``(1 - L kv) qd + (1 + L kv) qd_d - L kp Jbar e``: it grows with the sensed
    speed (``1 - L kv`` = 0.2 at L = 20 ms, kv = 40). At a few mm/s the joints turn within the
    compensation's ramp (``ServoGains.coulomb_velocity_rad_s``, 0.01 rad/s), where the
    compensation then grows with the joint's speed faster than the servo damps it: a negative
    damping, and the tool hunted between 0.73 and 1.23 times its SPEED at 5 mm/s (+Y, seeds 0
    and 2). With ``(2 xd_d - xd) / L`` in place of ``xd_d / L`` the intent is
    ``2 qd_d - L kv (qd - qd_d) - L kp Jbar e``: the reference's joint speeds, twice, as the
    trajectory's intent is when tracked, and a compensation that falls as a joint runs ahead
    of its reference, damping it. Only while the reference moves: at rest the sensed speed's
    noise would reach the compensation through ``-L kv xd`` (the tool did not settle).

    Args:
        command: ``F*_m``, world, in [m/s^2] then [rad/s^2]. # (6,)
        velocity: The sensed twist ``xd``, world, in [m/s] then [rad/s]. # (6,)
        reference_velocity: The reference's ``xd_d``, world. # (6,)
        lookahead_s: L, the intent's look-ahead, in [s].
    """
    return np.asarray(command) + (2.0 * np.asarray(reference_velocity) - np.asarray(velocity)) / lookahead_s


def next_leg(
    cruise: tuple[float, float],
    line_before: FloatArray,
    line: FloatArray,
    error: FloatArray,
    kp: float,
    limit: float,
) -> tuple[float, float]:
    """The cruise's ``(a, v_m)`` on a goal motion's next leg (MOVE ... VIA), from the leg before.

    The unmodelled force is the arm's, not the leg's: a joint's friction error keeps its sign
    while the joint turns the same way, a link's weight error stays. The leg before tells it
    whole, as a unit-mass acceleration ``d``: along its line ``u_0`` the integral held it,
    ``d . u_0 = -a``; across the line eq. 21 kept on it (:func:`cosmos.osc.motion.on_the_line`)
    commands ``-kp e_perp - kv xd_perp``, so a steady deviation ``e_perp`` from the line balances
    ``d_perp = kp e_perp`` (the position is measured far better than the speed: the velocity
    term is left out). The next leg along ``u`` starts with ``a = -d . u`` (clamped to
    ``+-limit``), and ``v_m``, the ideal unit mass's speed along the line, with the model's own
    velocity ``v_m u_0`` seen along ``u``. At a 45 deg turn on the realistic plant (seed 0, SPEED
    20 mm/s) this started the leg at ``a`` = -0.30 m/s^2 where it settled at -0.34, against 0.

    Args:
        cruise: ``(a [m/s^2], v_m [m/s])`` at the end of the leg before.
        line_before: That leg's unit line, world (zeros: none, or the field had it). # (3,)
        line: The next leg's unit line, world. # (3,)
        error: ``x - x_d`` at the end of the leg before (its goal the via point), world, [m]. # (3,)
        kp: The translation's unit-mass position gain, in [1/s^2].
        limit: The integral's clamp, in [m/s^2].

    Returns:
        The next leg's ``(a, v_m)``; ``(0, 0)`` when either leg has no line (as a new motion).
    """
    u0, u = np.asarray(line_before, dtype=float), np.asarray(line, dtype=float)
    if not np.any(u0) or not np.any(u):
        return 0.0, 0.0
    e = np.asarray(error, dtype=float)[:3]
    disturbance = kp * (e - float(e.dot(u0)) * u0) - cruise[0] * u0
    turn = float(u0.dot(u))
    return float(np.clip(-disturbance.dot(u), -limit, limit)), cruise[1] * turn


def leg_start_speed(velocity: FloatArray, line: FloatArray) -> float:
    """The speed from which eq. 21's limit ramps up on a goal motion's next leg: ``max(u . xd, 0)``, [m/s].

    A leg's unmodelled force is not the leg before's where a joint turns back (its friction
    error changes sign): at a 135 deg turn on the realistic plant (seed 0, SPEED 20 mm/s) the
    next leg ran at 26.7 mm/s over 20 ms while the integral learnt it again. Ramped up from the
    speed the tool already has along the new line (:func:`cosmos.osc.motion.goal_ramp_acceleration`),
    a slight turn keeps its speed, and a sharp one starts again as a new motion does.

    Args:
        velocity: The tool's velocity, world, in [m/s]. # (3,)
        line: The new leg's unit line, world. # (3,)
    """
    return max(float(np.dot(velocity[:3], line)), 0.0)
