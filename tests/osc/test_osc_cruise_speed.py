"""The cruise-speed integral of a goal motion (cosmos.osc.cruise_speed) and its compiled twin.

The analytic checks integrate the unit mass of eq. 20-21 along its line,
``dv/dt = kv (V - v) + a + d``, with a known steady disturbance ``d``: the speed it must
settle to is ``V`` (independent of the code), and without ``d`` the closed-form
``V (1 - e^{-kv t})`` of eq. 20 alone.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.cruise_speed import (
    breaks_away,
    cruise_command,
    cruise_integral_step,
    cruise_intent,
    speed_limit_binds,
    tracked_intent,
)
from cosmos.runtime.kernels import servo as sk
from cosmos.runtime.kernels.cruise import (
    BREAKAWAY,
    CRUISE,
    CRUISE_INTEGRAL,
    CRUISE_SLOTS,
    CRUISE_TURNS,
    LANDING,
    TRACKED_UNTIL,
    cruise_into,
    reference_speed,
)

KP, KV, DT_S = 400.0, 40.0, 0.001
GATE = (400.0, 2.0, 0.25, 2.0)


def _compiled(
    motion: np.ndarray,
    cruise: np.ndarray,
    error: np.ndarray,
    line: np.ndarray,
    velocity: np.ndarray,
    force: np.ndarray,
    speed: float,
    turns: bool = False,
    breakaway: bool = True,
) -> tuple[bool, np.ndarray]:
    """One compiled step on the servo's own layout; ``(binds, commanded speed)``, ``cruise`` stepped."""
    state = np.zeros((sk.STATE_ROWS, 6))
    state[sk.WRENCH], state[sk.ERROR], state[sk.VELOCITY], state[CRUISE, :2] = force, error, velocity, cruise
    scalars = np.zeros(sk.SCALARS)
    scalars[CRUISE_INTEGRAL : CRUISE_INTEGRAL + CRUISE_SLOTS] = (
        GATE[1],
        GATE[2],
        GATE[3],
        DT_S,
        GATE[0],
        KP / KV,
        KV,
    )
    scalars[CRUISE_TURNS] = float(turns)
    state[CRUISE, BREAKAWAY] = float(breakaway)
    commanded = np.full(6, np.nan)
    binds = cruise_into(motion, commanded, state, line, speed, scalars)
    cruise[:] = state[CRUISE, :2]
    return binds, commanded


LINE = np.array([0.0, 0.6, -0.8])


def _unit_mass(speed: float, disturbance: float, seconds: float) -> tuple[np.ndarray, float]:
    """Speeds along the line, one per tick, of the unit mass cruising far from its goal; the final a."""
    cruise, v, speeds = (0.0, 0.0), 0.0, []
    error = -1.0 * np.concatenate((LINE, np.zeros(3)))  # a metre short of the goal: the limit binds
    for _ in range(int(seconds / DT_S)):
        velocity = np.concatenate((v * LINE, np.zeros(3)))
        binds = speed_limit_binds(error, np.full(6, KP), np.full(6, KV), speed, LINE)
        cruise = cruise_integral_step(
            cruise, LINE, velocity, np.zeros(6), speed, binds, (KV, KP / KV), DT_S, GATE
        )
        v += DT_S * (KV * (speed - v) + cruise[0] + disturbance)
        speeds.append(v)
    return np.array(speeds), cruise[0]


@pytest.mark.parametrize(
    ("speed", "disturbance"),
    [(0.005, -0.1), (0.005, 0.3), (0.010, -0.25), (0.010, 0.3), (0.250, -1.5), (0.250, 1.5)],
)
def test_a_steady_disturbance_leaves_no_speed_error(speed: float, disturbance: float) -> None:
    """Catches eq. 20's proportional velocity loop alone: a steady unmodelled 0.3 m/s^2 holds the
    tool ``d / kv`` (7.5 mm/s) off its SPEED, 75 % at 10 mm/s; the integral must take it out
    (to 1 % within 0.5 s) and settle at ``-d``. A retarding one up to ``(1 - moving) kv V``, what
    the gate takes for a block, included."""
    speeds, integral = _unit_mass(speed, disturbance, 1.0)
    assert abs(speeds[500:].mean() - speed) < 0.01 * speed
    assert abs(speeds[-1] - speed) < 0.002 * speed
    assert integral == pytest.approx(-disturbance, rel=0.01)


def test_without_a_disturbance_the_motion_is_eq_20s() -> None:
    """Catches an integral on ``V - v`` rather than on what the model does not explain: the
    start's own lag winds it up and the speed overshoots (115 mm/s at 100 mm/s). Without a
    disturbance the speed must be eq. 20's ``V (1 - e^{-kv t})`` and the integral stay zero."""
    speeds, integral = _unit_mass(0.1, 0.0, 0.5)
    t = DT_S * np.arange(1, len(speeds) + 1)
    expected = 0.1 * (1.0 - (1.0 - KV * DT_S) ** np.arange(1, len(speeds) + 1))  # Euler's e^{-kv t}
    assert np.allclose(speeds, expected, atol=1e-9)
    assert np.allclose(expected, 0.1 * (1.0 - np.exp(-KV * t)), atol=0.003)
    assert abs(integral) < 1e-12


def test_without_a_line_it_neither_grows_nor_acts() -> None:
    """Catches an integral that fights an obstacle's field: while the field pushes the tool the
    servo's line is zeros, and the integral must stay as it was and add nothing."""
    velocity = np.array([0.0, 0.001, 0.0, 0.0, 0.0, 0.0])
    step = cruise_integral_step(
        (0.5, 0.01), np.zeros(3), velocity, np.zeros(6), 0.01, True, (KV, 10.0), DT_S, GATE
    )
    assert step == (0.5, 0.01)
    motion = np.zeros(6)
    cruise = np.array([0.5, 0.01])
    error = np.array([0.0, -1.0, 0.0, 0.0, 0.0, 0.0])
    zeros = np.zeros(3)
    binds, commanded = _compiled(motion, cruise, error, zeros, velocity, np.zeros(6), 0.01)
    assert not binds and not commanded.any()
    assert not motion.any() and list(cruise) == [0.5, 0.01]
    assert not cruise_intent(True, zeros, velocity, np.ones(6), KV, True).any()


def test_a_stalled_tool_breaks_away_drops_a_hold_back_and_freezes_on_a_push() -> None:
    """Catches a frozen integral that holds back a tool it stalled (a 5 mm/s MOVE stood still),
    one that leaves a tool stalled from rest with nothing pushing back (the gripper's CONTACT at
    3-5 mm/s never started on the realistic PUMA: the joints' static friction), and one that
    keeps winding up against whatever blocks the tool with a push (it must freeze)."""
    stalled = np.zeros(6)
    args = (LINE, stalled, np.zeros(6), 0.01, True, (KV, 10.0), DT_S, GATE)
    grown = cruise_integral_step((0.8, 0.01), *args)[0]
    assert grown == pytest.approx(0.8 + GATE[0] * 0.01 * DT_S)  # k_c (v_m - u . xd)
    assert cruise_integral_step((GATE[1] - 1e-6, 0.01), *args)[0] == GATE[1]  # bounded by the clamp
    assert cruise_integral_step((0.8, 0.0), *args)[0] == 0.8  # nothing the model expects: nothing
    assert cruise_integral_step((0.8, 0.01), *args, False)[0] == 0.8  # a fast motion's: frozen
    backwards = np.concatenate((-0.005 * LINE, np.zeros(3)))  # carried back: no breakaway
    back = (LINE, backwards, np.zeros(6), 0.01, True, (KV, 10.0), DT_S, GATE)
    assert cruise_integral_step((0.8, 0.01), *back)[0] == 0.8
    assert breaks_away(0.01) and not breaks_away(0.02)  # slow motions only
    held = cruise_integral_step((-0.3, 0.01), *args)[0]
    assert held == pytest.approx(-0.3 + GATE[0] * 0.01 * DT_S)
    assert cruise_integral_step((-0.001, 0.01), *args)[0] == 0.0  # lets go, never turns into a push
    pushed = np.array([0.0, 0.0, 5.0, 0.0, 0.0, 0.0])  # a touch: frozen
    moving = np.concatenate((0.005 * LINE, np.zeros(3)))
    assert (
        cruise_integral_step((0.8, 0.01), LINE, moving, pushed, 0.01, True, (KV, 10.0), DT_S, GATE)[0] == 0.8
    )


def test_it_bleeds_out_at_the_approach_rate_once_the_limit_lets_go() -> None:
    """Catches an integral kept on into the approach (the tool pushed past its goal, ``a / kp``):
    with ``nu = 1`` it must decay as ``e^{-(kp/kv) t}``."""
    cruise = (1.0, 0.01)
    for _ in range(200):
        cruise = cruise_integral_step(
            cruise, LINE, np.zeros(6), np.zeros(6), 0.01, False, (KV, KP / KV), DT_S, GATE
        )
    assert cruise[0] == pytest.approx(math.exp(-KP / KV * 0.2), rel=0.02)
    assert cruise_command(cruise[0], LINE)[:3] == pytest.approx(cruise[0] * LINE)


def test_the_limit_binds_where_eq_21s_nu_drops_below_one() -> None:
    """Catches a wrong ``nu``: it binds where ``(kp / kv) |x_d - x| > V_max`` and not closer, and
    not past the goal (there the integral held a tool at its SPEED 38 mm past a MOVE BY's goal:
    tests/run/test_run_payload.py)."""
    gains = np.full(6, KP), np.full(6, KV)
    down = np.array([0.0, 0.0, -1.0])  # the goal below the tool
    assert speed_limit_binds(np.array([0.0, 0.0, 0.0011, 0.0, 0.0, 0.0]), *gains, 0.01, down)
    assert not speed_limit_binds(np.array([0.0, 0.0, 0.0009, 0.0, 0.0, 0.0]), *gains, 0.01, down)
    assert not speed_limit_binds(np.array([0.0, 0.0, 0.0011, 0.0, 0.0, 0.0]), *gains, 0.01, -down)


def test_the_compiled_step_matches_the_reference_on_random_inputs() -> None:
    """Catches the servo kernel's arithmetic drifting from the readable reference (gates, clamp,
    model, bleed, the intent and the command), on seeded random inputs around every gate."""
    rng = np.random.default_rng(14)
    for _ in range(400):
        line = rng.normal(size=3)
        line = line / np.linalg.norm(line) if rng.random() > 0.1 else np.zeros(3)
        speed = float(rng.uniform(0.005, 0.25))
        error = np.concatenate((rng.normal(size=3) * rng.choice([1e-4, 1e-3, 0.1]), rng.normal(size=3)))
        velocity = np.concatenate(
            (line * speed * rng.uniform(-0.5, 1.5) + rng.normal(size=3) * 1e-3, np.zeros(3))
        )
        force = rng.normal(size=6) * rng.choice([0.1, 3.0])
        cruise = (float(rng.uniform(-2.5, 2.5)), float(rng.uniform(0.0, 0.3)))
        kp, kv = np.full(6, KP), np.full(6, KV)
        binds = speed_limit_binds(error, kp, kv, speed, line)
        breakaway = bool(rng.random() > 0.3)
        expected = cruise_integral_step(
            cruise, line, velocity, force, speed, binds, (KV, KP / KV), DT_S, GATE, breakaway
        )
        motion = rng.normal(size=6)
        before = motion.copy()
        state = np.array(cruise)
        turns = bool(rng.random() > 0.5)
        got, commanded = _compiled(motion, state, error, line, velocity, force, speed, turns, breakaway)
        assert state == pytest.approx(np.array(expected), abs=1e-12)
        assert motion - before == pytest.approx(cruise_command(expected[0], line), abs=1e-12)
        assert commanded == pytest.approx(cruise_intent(binds, line, velocity, before, KV, turns), abs=1e-12)
        assert got == (binds and bool(line.any()))


def test_the_servo_kernel_layout_leaves_the_cruise_its_slots() -> None:
    """Catches the cruise's slots overlapping another's: its seven scalars are followed only by an
    INSERT's push's speed reference's rate, its state row the last (an INSERT's push keeps its speed
    reference at 2 and 3: the cruise integral never runs there), and it reads the wrench, error and
    twist from rows 0-2."""
    assert sk.PUSH_SPEED_RATE == CRUISE_INTEGRAL + CRUISE_SLOTS
    assert sk.PUSH_SPEED_RATE + 1 == TRACKED_UNTIL  # a slow MOVE's
    assert sk.TOUCH_FREE_SPEED == TRACKED_UNTIL + 1 and CRUISE_TURNS == sk.TOUCH_FREE_SPEED + 1  # CONTACT's
    assert sk.TILT_WINDOW == LANDING + 3 and LANDING == CRUISE_TURNS + 1  # a CONTACT's landing (osc.landing)
    assert sk.SCALARS == sk.TILT_WINDOW + 7  # an INSERT's compliant axes last (osc.tilt_window)
    assert sk.HOLD_OBSERVER + 4 <= CRUISE_INTEGRAL
    assert sk.STATE_ROWS > CRUISE and sk.MOTION_INTEGRAL < CRUISE  # the springs' rows follow (kernels.spring)
    assert (sk.WRENCH, sk.ERROR, sk.VELOCITY) == (0, 1, 2)


LOOKAHEAD_S = 0.02


def _friction_intent(tracked: bool, v: float, v_d: float, e: float) -> float:
    """The Coulomb intent ``qd + L Jbar a`` of a unit mass on one axis (``J = Jbar = 1``), eq. 19."""
    command = np.array([-KP * e - KV * (v - v_d), 0, 0, 0, 0, 0], dtype=float)
    velocity, reference = np.array([v, 0, 0, 0, 0, 0.0]), np.array([v_d, 0, 0, 0, 0, 0.0])
    if tracked:
        a = tracked_intent(command, velocity, reference, LOOKAHEAD_S)
    else:  # a trajectory's: F*_m + xd_d / L (kernels.servo)
        a = command + reference / LOOKAHEAD_S
    return v + LOOKAHEAD_S * float(a[0])


def test_a_slow_references_intent_damps_a_joint_running_ahead() -> None:
    """Catches the friction's intent of a tracked trajectory rising with the sensed speed: its
    slope ``1 - L kv`` (0.2) times the compensation's ramp (full at 0.01 rad/s) outweighed the
    servo's damping, and a 5 mm/s MOVE hunted between 0.73 and 1.23 times its SPEED. Against
    the analytic intent ``2 v_d - L kv (v - v_d) - L kp e``: its slope in ``v`` is ``-L kv``."""
    v_d, e, dv = 0.004, 2e-4, 1e-4
    slope = (_friction_intent(True, v_d + dv, v_d, e) - _friction_intent(True, v_d - dv, v_d, e)) / (2 * dv)
    assert slope == pytest.approx(-LOOKAHEAD_S * KV, rel=1e-9)
    assert _friction_intent(True, v_d, v_d, 0.0) == pytest.approx(2.0 * v_d, rel=1e-12)
    assert _friction_intent(True, 0.0, v_d, e) == pytest.approx(
        2 * v_d + LOOKAHEAD_S * KV * v_d - LOOKAHEAD_S * KP * e, rel=1e-12
    )
    before = (_friction_intent(False, v_d + dv, v_d, e) - _friction_intent(False, v_d - dv, v_d, e)) / (
        2 * dv
    )
    assert before == pytest.approx(1.0 - LOOKAHEAD_S * KV, rel=1e-9) and before > 0.0


def test_the_compiled_reference_speed_matches_the_reference() -> None:
    """Catches the compiled intent's speed drifting from cosmos.osc.cruise_speed.tracked_intent
    while a slow MOVE's reference moves, or staying so after it stops (at rest the sensed
    speed's noise reached the compensation and the tool did not settle), or touching any other
    trajectory (its slot 0: ``xd_d`` off the force axes, as before)."""
    rng = np.random.default_rng(14)
    for _ in range(50):
        reference, velocity, command = rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
        omega_bar = np.diag(rng.choice([0.0, 1.0], size=6))
        scalars = np.zeros(sk.SCALARS)
        free = reference - omega_bar @ reference
        assert reference_speed(reference, omega_bar, velocity, scalars, 1.0) == pytest.approx(free, abs=1e-12)
        scalars[TRACKED_UNTIL] = 2.0
        moving = reference_speed(reference, omega_bar, velocity, scalars, 1.999)
        expected = tracked_intent(command, velocity, free, LOOKAHEAD_S)
        assert command + moving / LOOKAHEAD_S == pytest.approx(expected, rel=1e-12, abs=1e-9)
        assert reference_speed(reference, omega_bar, velocity, scalars, 2.0) == pytest.approx(free, abs=1e-12)
