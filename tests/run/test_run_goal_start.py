"""A goal motion (eq. 20-21) starts from rest without a step and keeps to its line.

Eq. 20-21 command ``kv (nu xd_d - xd)``; from rest, far from the goal, that is a step
of ``kv V_max`` (10 m/s^2 at 0.25 m/s), twice the arm's declared 5 m/s^2, which put
70 N m on the PUMA's joint 1 within one servo tick. The speed limit now ramps up at
the arm's acceleration ``a`` (:func:`cosmos.osc.motion.ramped_speed_limit`): a unit
mass at rest then follows ``v(t) = a (t - (1 - e^{-kv t}) / kv)`` until the limit is
reached (``t = V / a``), commanded ``a (1 - e^{-kv t})``, never more than ``a``
(:func:`cosmos.osc.motion.goal_ramp_acceleration`: ``a`` is at most ``V / 0.3 s``). The
runs log the tool's twist every servo tick (``state_hz`` 1000).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from run_support import BOTH_PLANTS

from cosmos.api import check
from cosmos.capabilities import ARM_CAPABILITY
from cosmos.execution.session import Session
from cosmos.osc.motion import goal_ramp_acceleration
from cosmos.runlog.reader import RunRecord, read_log
from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import DEFAULT_KV

SPEED_MPS = 0.25
PROGRAM = f"SPEED {SPEED_MPS:g} m/s\nWAIT 0.2 s\nMOVE BY (0, 0.1 m, 0)\n"
MOVE_LINE = 3
ACCELERATION = goal_ramp_acceleration(SPEED_MPS, ARM_CAPABILITY.tool_acceleration_mps2)
"""The arm's 5 m/s^2, or less: a MOVE reaches its SPEED no sooner than 0.3 s after it starts."""


def run(tmp_path: Path, ideal: bool) -> RunRecord:
    plan = check(PROGRAM)
    path = tmp_path / "start.mcap"
    with Session("<test>", plan.source, path, Rates(state_hz=1000.0), ideal=ideal) as session:
        session.executor.run(plan)
    return read_log(path)


def analytic_speed(t: np.ndarray) -> np.ndarray:
    """``a (t - (1 - e^{-kv t}) / kv)``: a unit mass at rest under the ramped limit, [m/s]."""
    return ACCELERATION * (t - (1.0 - np.exp(-DEFAULT_KV * t)) / DEFAULT_KV)


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_a_goal_motion_from_rest_accelerates_at_the_arms_rate(tmp_path: Path, ideal: bool) -> None:
    """Over the ramp (the first V / a = 0.3 s) the tool's speed stays under ``a t`` (what no
    more than ``a`` allows) and, on the ideal plant, follows the analytic response; the
    arm's torques never jump by more than the ramp asks in a tick. Catches eq. 20-21's step
    from rest (the speed reached 0.17 m/s by 30 ms against 0.15 allowed; joint 1's torque
    stepped by 70 N m in one tick) and a ramp that starts from the wrong time or speed."""
    record = run(tmp_path, ideal)
    state = record.state
    moving = state.line == MOVE_LINE
    t = state.t[moving] - state.t[moving][0]
    speed = np.linalg.norm(state.v[moving, :3], axis=1)
    ramp = t <= SPEED_MPS / ACCELERATION
    noise = 0.0 if ideal else 0.010  # the observer's velocity noise on the realistic plant
    excess = speed[ramp] - (ACCELERATION * t[ramp] + 0.001 + noise)
    assert excess.max() <= 0.0, f"{excess.max() * 1e3:.1f} mm/s over a t at {t[ramp][excess.argmax()]:.3f} s"
    if ideal:
        expected = analytic_speed(t[ramp])
        error = np.abs(speed[ramp] - expected)
        assert error.max() < 0.04 * SPEED_MPS, f"{error.max() * 1e3:.1f} mm/s off the analytic response"
    steps = np.abs(np.diff(state.tau[moving][:60], axis=0)).max()
    assert steps < 10.0, f"a torque step of {steps:.1f} N m in one tick"
    assert math.isclose(speed[~ramp].max(), SPEED_MPS, rel_tol=0.1), speed.max()


LINE_PROGRAM = "SPEED 0.25 m/s\nMOVE BY (0, 0.3 m, 0)\n"


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_a_goal_motion_keeps_to_its_line(tmp_path: Path, ideal: bool) -> None:
    """A 0.3 m MOVE BY at 0.25 m/s: the tool within 0.6 mm of its straight line throughout.
    Catches eq. 21's speed limit scaling the correction across the line by ``V_max / |x_d - x|``
    (0.94 mm off the line on the realistic PUMA, 2.4 mm on the realistic Panda)."""
    plan = check(LINE_PROGRAM)
    path = tmp_path / "line.mcap"
    with Session("<test>", plan.source, path, Rates(), ideal=ideal) as session:
        session.executor.run(plan)
    state = read_log(path).state
    x = state.x[state.line == 2, :3]
    u = np.array((0.0, 1.0, 0.0))
    along = np.clip((x - x[0]) @ u, 0.0, 0.3)
    deviation = np.linalg.norm(x - x[0] - np.outer(along, u), axis=1).max()
    assert deviation < 0.6e-3, f"{deviation * 1e3:.2f} mm off its line"
