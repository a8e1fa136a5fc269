"""Goal motion with a speed limit (seed eq. 20-21) and the two-level architecture (section 3).

Eq. 21 points the desired velocity at the goal and caps its magnitude at
V_max, so between the acceleration and deceleration the tool travels in a
straight line at V_max, and the critically damped approach (kp, kv = 2 sqrt(kp))
does not overshoot.

On the realistic plant (cosmos.realism) the drives' friction is up to 10 % off the
published levels the controller compensates (by direction): a torque disturbance while
the joints move, which eq. 21 at its speed limit resists only
weakly across the line (``kv V_max / D``, ``D`` the distance left). The limits add what a
reduced model of that (tests/runtime/friction_error.py) predicts for the run, 1.5 times
(over seeds 0-2 the runs left the line by 0.74-1.13 times its prediction), to the ideal plant's.
"""

from __future__ import annotations

import numpy as np

from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint
from tests.runtime.friction_error import LineErrorModel
from tests.runtime.runtime_helpers import run_for, runtime_at

V_MAX = 0.25
DISPLACEMENT = np.array((-0.24, 0.32, 0.0))  # 0.4 m


MODEL_MARGIN = 1.5
"""The reduced friction-error model's prediction times this is what the realistic plant may add."""


def straight_move(
    rates: Rates, model: list[LineErrorModel] | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Run the 0.4 m move; return times, true tool positions, start and goal.

    ``model``: if given, gets the friction-error model of the run appended.
    """
    runtime = runtime_at(rates=rates)
    run_for(runtime, 0.2)
    start = runtime.plant.data.site("tool").xpos.copy()
    goal = start + DISPLACEMENT
    ev = runtime.evaluation
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.GOAL,
            position=goal,
            rotation_to_world=ev.rotation_tool_to_world.copy(),
            start_s=runtime.time_s,
            max_speed=V_MAX,
        )
    )
    if model is None:
        samples = run_for(runtime, 2.6)
    else:
        predicted = LineErrorModel(start, goal, V_MAX, 1.0 / rates.servo_hz)
        model.append(predicted)
        site = runtime.plant.model.site("tool").id
        samples = []
        for _ in range(round(2.6 * rates.servo_hz)):
            runtime.tick()
            tool = runtime.plant.data.site_xpos[site].copy()
            predicted.step(runtime, tool)
            samples.append((runtime.time_s, tool))
    return np.array([s[0] for s in samples]), np.array([s[1] for s in samples]), start, goal


def line_deviation(positions: np.ndarray, start: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """Distance of each position from the line through start and goal [m]."""
    direction = (goal - start) / np.linalg.norm(goal - start)
    offsets = positions - start
    return np.linalg.norm(offsets - np.outer(offsets @ direction, direction), axis=1)


def test_straight_line_at_the_speed_limit() -> None:
    """Catches a goal motion that leaves the line, misses V_max or overshoots, beyond the ideal
    plant's 2 mm, 5 % and 1 mm and what the realistic plant's friction error explains."""
    models: list[LineErrorModel] = []
    t, positions, start, goal = straight_move(Rates(), models)
    (model,) = models
    direction = DISPLACEMENT / np.linalg.norm(DISPLACEMENT)
    progress = (positions - start) @ direction
    deviation = line_deviation(positions, start, goal)
    line_limit = 0.002 + MODEL_MARGIN * model.largest_error_m
    assert deviation.max() < line_limit, (
        f"left the line by {deviation.max() * 1e3:.2f} mm (limit {line_limit * 1e3:.2f} mm)"
    )
    speed = np.gradient(progress, t)
    # Cruise: away from the first and last 60 mm, where the tool accelerates and brakes.
    cruise = (progress > 0.06) & (progress < 0.34)
    assert cruise.sum() > 500
    speed_limit = 0.05 * V_MAX + MODEL_MARGIN * model.largest_speed_error_m_s
    assert np.all(np.abs(speed[cruise] - V_MAX) < speed_limit), (
        f"cruise speed {speed[cruise].min():.4f}..{speed[cruise].max():.4f} m/s (+-{speed_limit:.4f})"
    )
    overshoot = progress.max() - np.linalg.norm(DISPLACEMENT)
    assert overshoot < 0.001, f"overshoot {overshoot * 1e3:.2f} mm"
    assert np.linalg.norm(positions[-1] - goal) < 0.002


def test_parameters_at_a_fifth_of_the_servo_rate_track_within_twice_the_error() -> None:
    every_tick = straight_move(Rates(servo_hz=1000.0, param_hz=1000.0))
    fifth = straight_move(Rates(servo_hz=1000.0, param_hz=200.0))
    error_every = line_deviation(every_tick[1], every_tick[2], every_tick[3]).max()
    error_fifth = line_deviation(fifth[1], fifth[2], fifth[3]).max()
    assert error_fifth <= 2.0 * error_every, (
        f"{error_fifth * 1e3:.3f} mm at 200 Hz vs {error_every * 1e3:.3f} mm at 1 kHz"
    )


def test_the_seeds_own_rates_run() -> None:
    """225 Hz servo, 100 Hz evaluation (seed section 7) reach the goal of the same move."""
    models: list[LineErrorModel] = []
    t, positions, start, goal = straight_move(Rates(servo_hz=225.0, param_hz=100.0), models)
    assert np.linalg.norm(positions[-1] - goal) < 0.002
    assert line_deviation(positions, start, goal).max() < 0.005 + MODEL_MARGIN * models[0].largest_error_m
