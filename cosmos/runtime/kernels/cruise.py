"""A goal motion's cruise-speed integral, compiled (numba): :mod:`cosmos.osc.cruise_speed`.

``tests/osc/test_osc_cruise_speed.py`` checks it against the readable reference on seeded
random inputs and at its gates. Its slots in the servo kernel's packed arrays
(:mod:`cosmos.runtime.kernels.servo`) are laid out here.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.cruise_speed import breaks_away, leg_start_speed, next_leg
from cosmos.osc.landing import LANDING_OVER_M
from cosmos.osc.motion import PoseTrajectory
from cosmos.runtime.kernels.linear import matvec
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

FloatArray = np.ndarray

CRUISE = 10
"""Row of the servo's ``state``: the integral ``a`` [m/s^2] and the model speed ``v_m`` [m/s].
Rows 0-2 are the servo's wrench, error ``x - x_d`` and twist (kernels.servo's WRENCH, ERROR,
VELOCITY), world."""
BREAKAWAY = 4
"""Column of :data:`CRUISE`, set per segment (:func:`restart`): 1 where a tool at rest with nothing
pushing back grows the integral (:func:`cosmos.osc.cruise_speed.breaks_away`), else 0. Columns 2-3
are an INSERT's push's speed reference (kernels.push_speed), where no cruise integral runs."""
CRUISE_INTEGRAL = 49
"""First of seven ``scalars`` (49-55; kernels.servo's PUSH_SPEED_RATE follows), set per segment
(:func:`cruise_gains`): limit [m/s^2], moving [1], quiet [N], dt [s], k_c [1/s^2] (0: no
cruise integral), the smallest ``kp / kv`` [1/s] and ``kv`` [1/s]."""
CRUISE_SLOTS = 7
TRACKED_UNTIL = 57
"""The servo's scalar 57 (kernels.servo's TOUCH_FREE_SPEED next), set per segment (:func:`tracked_until`):
until when [s] a slow MOVE's tracked reference moves (a free trajectory with cruise timing and
uniform gains: :func:`cosmos.execution.resolve.tracks_a_reference`), its Coulomb intent reading
the reference (:func:`reference_speed`) from :data:`TRACKED_INTENT_MPS` on; 0 for any other segment."""
CRUISE_TURNS = 59
"""The servo's scalar 59 (kernels.servo's TOUCH_FREE_SPEED before it, :data:`LANDING` after), set per
segment (:func:`restart`): 1 where the cruise's Coulomb intent covers the rotation too (every
rotation motion-controlled, the orientation the task's), else 0
(:func:`cosmos.osc.cruise_speed.cruise_intent`)."""
LANDED = 5
"""Columns 5-6 of :data:`CRUISE`, each tick (:func:`landing_into`): 1 where eq. 21's limit is on a
CONTACT's landing profile, else 0; the profile's deceleration ``a_ff`` [m/s^2]."""
LANDING = 60
"""The servo's scalars 60-62 (kernels.servo's TILT_WINDOW follows), set per segment (:func:`restart`) from
``ServoSetpoint.landing``: a CONTACT's landing on a stiff surface (:mod:`cosmos.osc.landing`): ``s_l``,
the distance from the goal along its line where the landing speed must be held [m], ``v_l`` [m/s]
(0: no landing), ``a`` [m/s^2]."""
TRACKED_INTENT_MPS = 0.0025
"""A slower reference leaves the intent as a trajectory's [m/s]. That intent weighs the sensed
speed ``L kv`` = 0.8 where a trajectory's weighs it ``1 - L kv`` = 0.2, and at a few mm/s the
reference's joint speeds (under 5e-3 rad/s) are below the velocity observer's noise on the
realistic plant (one count through 40 Hz: 9e-3 rad/s at joint 1): at 1 mm/s 2 of 18 cases
(seeds 0-4, ideal; +Y, down, diagonal) held their SPEED within the bar, against 12 of 18,
and at 2 mm/s along +Y the median ran 4-5 % fast (0.0-0.2 % with a trajectory's intent)."""


def cruise_gains(
    gains: tuple[float, float, float, float], dt_s: float, setpoint: ServoSetpoint
) -> FloatArray:
    """A segment's seven slots at :data:`CRUISE_INTEGRAL`; k_c 0 unless a goal motion with no force axis.

    Args:
        gains: ``ServoGains.cruise_integral``: ``(k_c [1/s^2], limit [m/s^2], moving [1], quiet [N])``.
        dt_s: Servo period, in [s].
        setpoint: The segment.
    """
    k_c, limit, moving, quiet = gains
    free_goal = setpoint.mode is MotionMode.GOAL and all(setpoint.motion_axes[:3])
    free_goal = free_goal and setpoint.cruise_integral
    kp, kv = np.asarray(setpoint.kp_task[:3]), np.asarray(setpoint.kv_task[:3])
    ratio, rate = float(np.min(kp / kv)), float(np.min(kv))
    return np.array((limit, moving, quiet, dt_s, k_c if free_goal else 0.0, ratio, rate))


def tracked_until(setpoint: ServoSetpoint) -> float:
    """The slot :data:`TRACKED_UNTIL` of a segment: its reference's end [s], or 0 if it is none."""
    trajectory = setpoint.trajectory
    tracked = setpoint.mode is MotionMode.TRAJECTORY and all(setpoint.motion_axes) and setpoint.uniform_gains
    tracked = tracked and isinstance(trajectory, PoseTrajectory) and trajectory.cruise_ramp_s is not None
    tracked = tracked and setpoint.max_speed >= TRACKED_INTENT_MPS - 1e-9
    return setpoint.start_s + trajectory.duration_s if tracked and trajectory is not None else 0.0


def restart(
    state: FloatArray,
    previous: ServoSetpoint | None,
    setpoint: ServoSetpoint,
    line_before: FloatArray,
    line: FloatArray,
    scalars: FloatArray,
) -> tuple[float, float]:
    """Start a segment's cruise row at :data:`CRUISE`; return the speeds its limits ramp up from.

    A new motion starts ``(a, v_m)`` at zero, and eq. 21's limits ramp up from the tool's
    speeds (:func:`cosmos.osc.motion.ramped_speed_limit`). On the next leg of a goal motion
    (:meth:`ServoSetpoint.continues`: MOVE ... VIA) ``(a, v_m)`` carry over
    (:func:`cosmos.osc.cruise_speed.next_leg`), and the limit ramps up from the tool's speed
    along the new line (none where it turns back: :func:`cosmos.osc.cruise_speed.leg_start_speed`).

    Args:
        state: The servo's state; rows 1-2 (``x - x_d``, the twist) read, :data:`CRUISE` written.
            # (rows, >= 6)
        previous: The setpoint until now (None: none).
        setpoint: The new one.
        line_before: The line the kernel kept to until now, world. # (3,)
        line: The new goal line, world. # (3,)
        scalars: The servo's scalars; the integral's clamp at :data:`CRUISE_INTEGRAL` read,
            :data:`CRUISE_TURNS` written. # (SCALARS,)

    Returns:
        The start speeds of the translation [m/s] and the rotation [rad/s].
    """
    velocity = state[2, :6]
    speeds = float(np.linalg.norm(velocity[:3])), float(np.linalg.norm(velocity[3:]))
    carried = (0.0, 0.0)
    if setpoint.continues(previous):
        kp = float(np.min(setpoint.kp_task[:3]))
        before = (float(state[CRUISE, 0]), float(state[CRUISE, 1]))
        carried = next_leg(before, line_before, line, state[1, :3], kp, scalars[CRUISE_INTEGRAL])
        speeds = leg_start_speed(velocity[:3], line), speeds[1]
    state[CRUISE] = 0.0
    state[CRUISE, :2] = carried
    landing = setpoint.landing[1]  # a landing's slow end breaks away from rest too (cosmos.osc.landing)
    slow = breaks_away(setpoint.max_speed) or 0.0 < landing and breaks_away(landing)
    state[CRUISE, BREAKAWAY] = float(slow)
    scalars[CRUISE_TURNS] = float(all(setpoint.motion_axes[3:]) and not setpoint.orientation_free)
    scalars[LANDING : LANDING + 3] = setpoint.landing
    return speeds


@kernel
def landing_limit(max_speed: float, to_go: float, landing: float, deceleration: float) -> tuple[float, float]:
    """:func:`cosmos.osc.landing.landing_limit`: ``(V, a_ff)`` on a landing's braking profile."""
    if not landing > 0.0 or to_go < -LANDING_OVER_M:  # none, or past its surface untouched: over
        return max_speed, 0.0
    profile = math.sqrt(landing * landing + 2.0 * deceleration * max(to_go, 0.0))
    if profile >= max_speed:
        return max_speed, 0.0
    return profile, deceleration if to_go > 0.0 else 0.0


@kernel
def landing_into(
    max_speed: float, error: FloatArray, line: FloatArray, scalars: FloatArray, state: FloatArray
) -> float:
    """Eq. 21's ``V_max`` (ramped) on a CONTACT's landing profile (:data:`LANDING`); ``a_ff`` to ``state``.

    :func:`landing_limit` at ``s = u^T (x_d - x) - s_l``: returns the limit, and writes the profile's
    deceleration ``a_ff`` [m/s^2] (:func:`cruise_into` subtracts ``a_ff u`` from F*_m, fed forward) and
    whether the profile binds (:data:`LANDED`) into the cruise row.
    """
    cruise, landing = state[CRUISE], scalars[LANDING : LANDING + 3]
    cruise[LANDED], cruise[LANDED + 1] = 0.0, 0.0
    if not landing[1] > 0.0 or (line[0] == 0.0 and line[1] == 0.0 and line[2] == 0.0):  # none, or no line
        return max_speed
    to_go = -(error[0] * line[0] + error[1] * line[1] + error[2] * line[2]) - landing[0]
    limit, brake = landing_limit(max_speed, to_go, landing[1], landing[2])
    cruise[LANDED], cruise[LANDED + 1] = 1.0 if limit < max_speed else 0.0, brake
    return limit


@kernel
def cruise_into(
    motion: FloatArray,
    commanded_speed: FloatArray,
    state: FloatArray,
    line: FloatArray,
    max_speed: float,
    scalars: FloatArray,
) -> bool:
    """Step ``cruise = (a, v_m)`` (:func:`cosmos.osc.cruise_speed.cruise_integral_step`), add ``a u``.

    ``commanded_speed`` is set to zeros or, while a cruise's limit binds, to ``2 v_d - xd``
    (``motion`` on entry is ``kv (v_d - xd)``; the rotation's zeros unless :data:`CRUISE_TURNS`):
    the speed the Coulomb intent adds
    (:func:`cosmos.osc.cruise_speed.cruise_intent`); returns whether it binds. On a CONTACT's landing
    profile (:func:`landing_into`) the integral keeps what it learnt at the SPEED.

    Args:
        motion: F*_m, world; ``a u`` is added. # (6,)
        commanded_speed: Written, world, [m/s]. # (6,)
        state: The servo's state: rows 0-2 read, ``(a, v_m)`` at :data:`CRUISE` stepped. # (rows, >= 6)
        line: Unit line from the motion's start to its goal (zeros: none). # (3,)
        max_speed: Eq. 21's V_max now (ramped), in [m/s].
        scalars: The servo's scalars; the seven at :data:`CRUISE_INTEGRAL` are read. # (SCALARS,)
    """
    commanded_speed[:] = 0.0
    g = scalars[CRUISE_INTEGRAL : CRUISE_INTEGRAL + CRUISE_SLOTS]
    limit, moving, quiet, dt_s, k_c, ratio, kv = g[0], g[1], g[2], g[3], g[4], g[5], g[6]
    if k_c == 0.0 or (line[0] == 0.0 and line[1] == 0.0 and line[2] == 0.0):
        return False
    force, error, velocity, cruise = state[0], state[1], state[2], state[CRUISE]
    ahead = error[0] * line[0] + error[1] * line[1] + error[2] * line[2] < 0.0  # not past the goal
    binds = ahead and ratio * math.sqrt(error[0] ** 2 + error[1] ** 2 + error[2] ** 2) > max_speed
    landed = state[CRUISE, LANDED] != 0.0  # eq. 21's limit on a landing's profile (landing_into)
    along = velocity[0] * line[0] + velocity[1] * line[1] + velocity[2] * line[2]
    push = math.sqrt(force[0] ** 2 + force[1] ** 2 + force[2] ** 2)
    if landed:  # the cruise's integral as learnt at its SPEED: wound by the braking, it rang
        cruise[1] = max_speed
    elif not binds:
        cruise[0] *= max(0.0, 1.0 - ratio * dt_s)
        cruise[1] = along
    elif along > moving * max_speed and push < quiet:
        cruise[0] = min(max(cruise[0] + k_c * (cruise[1] - along) * dt_s, -limit), limit)
        cruise[1] += kv * (max_speed - cruise[1]) * dt_s
    else:  # stalled, blocked or touching: a held back lets go; a slow one at rest breaks away
        if cruise[0] < 0.0 and push < quiet:
            cruise[0] = min(cruise[0] + k_c * (max_speed - along) * dt_s, 0.0)
        elif cruise[BREAKAWAY] != 0.0 and push < quiet and along > -moving * max_speed:  # at rest, free
            cruise[0] = min(cruise[0] + k_c * max(cruise[1] - along, 0.0) * dt_s, limit)
        # The model runs on, drawn down at kp / kv toward the tool in a lasting stall.
        cruise[1] += kv * (max_speed - cruise[1]) * dt_s
        floor = along + moving * max_speed
        if cruise[1] > floor:
            cruise[1] += ratio * (floor - cruise[1]) * dt_s
    if binds:  # 2 v_d - xd, with F*_m = kv (v_d - xd) before a u
        for i in range(6 if scalars[CRUISE_TURNS] != 0.0 else 3):
            commanded_speed[i] = velocity[i] + 2.0 * motion[i] / kv
    for i in range(3):  # the integral's a u, and a landing's deceleration fed forward (landing_into)
        motion[i] += (cruise[0] - cruise[LANDED + 1]) * line[i]
    return binds


@kernel
def reference_speed(
    velocity_desired: FloatArray, omega_bar: FloatArray, velocity: FloatArray, scalars: FloatArray, t_s: float
) -> FloatArray:
    """A tracked trajectory's speed for the Coulomb intent, world: ``xd_d`` off the force axes. # (6,).

    While a slow MOVE's reference moves (until :data:`TRACKED_UNTIL`), ``2 xd_d - xd``: with the
    intent's ``F*_m`` it is :func:`cosmos.osc.cruise_speed.tracked_intent`.

    Args:
        velocity_desired: The reference's ``xd_d``, world. # (6,)
        omega_bar: The force axes' selection Omega_bar, world. # (6, 6)
        velocity: The sensed twist ``xd``, world. # (6,)
        scalars: The servo's scalars; :data:`TRACKED_UNTIL` is read. # (SCALARS,)
        t_s: Simulated time, in [s].
    """
    speed = velocity_desired - matvec(omega_bar, velocity_desired)
    if t_s < scalars[TRACKED_UNTIL]:
        for i in range(6):
            speed[i] = 2.0 * speed[i] - velocity[i]
    return speed
