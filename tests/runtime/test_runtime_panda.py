"""The PUMA's runtime figures reproduced on the seven-joint Panda, with the same tolerances.

The same controller code runs both arms (joint dimensions are the model's): on the
Panda a setpoint step must follow the analytic unit-mass response (the seed's eq. 17-19
decoupling, tests/runtime/test_runtime_decoupling.py) and a 0.4 m goal motion must run
straight at its speed limit (eq. 20-21, tests/runtime/test_runtime_goal_motion.py). For
a redundant arm J is 6 x 7, Lambda^-1 = J A^-1 J^T and Jbar = A^-1 J^T Lambda (eq. 27-28):
a kernel that kept a six-joint shape anywhere would not pass.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.robot_model import build_robot_model
from cosmos.robots import PANDA
from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import DEFAULT_KP, MotionMode, ServoSetpoint
from cosmos.workcell import home_q
from tests.runtime.runtime_helpers import run_for, runtime_at
from tests.runtime.test_runtime_decoupling import STEP_M, unit_mass_step
from tests.runtime.test_runtime_goal_motion import DISPLACEMENT, V_MAX, line_deviation

ROBOT = build_robot_model(PANDA)
HOME = home_q(PANDA)
CONFIGURATIONS = {
    "home": HOME,
    "elbow-out": HOME + np.array((0.4, 0.2, -0.5, 0.3, 0.3, -0.2, 0.5)),
}


@pytest.mark.parametrize("configuration", CONFIGURATIONS)
@pytest.mark.parametrize("axis", [0, 1, 2])
def test_step_follows_a_unit_mass_on_the_panda(configuration: str, axis: int) -> None:
    """Catches a coupling left by a wrong Lambda or Jbar for J of 6 x 7 (the response off the
    analytic curve, or motion on the other axes)."""
    runtime = runtime_at(CONFIGURATIONS[configuration], robot=ROBOT)
    assert runtime.q.shape == (7,)
    run_for(runtime, 0.2)
    start = runtime.plant.data.site("tool").xpos.copy()
    goal = start.copy()
    goal[axis] += STEP_M
    t0 = runtime.time_s
    rotation = runtime.evaluation.rotation_tool_to_world.copy()
    runtime.set_setpoint(ServoSetpoint(MotionMode.HOLD, goal, rotation, start_s=t0))
    samples = run_for(runtime, 1.0)
    t = np.array([s[0] for s in samples]) - t0
    moved = np.array([s[1] for s in samples]) - start
    deviation = np.abs(moved[:, axis] - unit_mass_step(t, STEP_M, DEFAULT_KP))
    others = np.delete(moved, axis, axis=1)
    assert deviation.max() < 0.05 * STEP_M, f"max deviation {deviation.max() * 1e3:.2f} mm"
    assert np.abs(others).max() < 0.02 * STEP_M, f"cross-axis motion {np.abs(others).max() * 1e3:.2f} mm"


def test_straight_line_at_the_speed_limit_on_the_panda() -> None:
    """0.4 m at 0.25 m/s: within 2 mm of the line, cruising within 5 % of V_max, overshoot under
    1 mm, ending within 2 mm (the PUMA's bar). Catches a redundant arm wandering off its line."""
    runtime = runtime_at(rates=Rates(), robot=ROBOT)
    run_for(runtime, 0.2)
    start = runtime.plant.data.site("tool").xpos.copy()
    goal = start + DISPLACEMENT
    rotation = runtime.evaluation.rotation_tool_to_world.copy()
    runtime.set_setpoint(
        ServoSetpoint(MotionMode.GOAL, goal, rotation, start_s=runtime.time_s, max_speed=V_MAX)
    )
    samples = run_for(runtime, 2.6)
    t = np.array([s[0] for s in samples])
    positions = np.array([s[1] for s in samples])
    direction = DISPLACEMENT / np.linalg.norm(DISPLACEMENT)
    progress = (positions - start) @ direction
    deviation = line_deviation(positions, start, goal)
    assert deviation.max() < 0.002, f"left the line by {deviation.max() * 1e3:.2f} mm"
    speed = np.gradient(progress, t)
    cruise = (progress > 0.06) & (progress < 0.34)
    assert cruise.sum() > 500
    assert np.all(np.abs(speed[cruise] - V_MAX) < 0.05 * V_MAX), (
        f"cruise speed {speed[cruise].min():.4f}..{speed[cruise].max():.4f} m/s"
    )
    assert progress.max() - np.linalg.norm(DISPLACEMENT) < 0.001
    assert np.linalg.norm(positions[-1] - goal) < 0.002
