"""A CONTACT's hold whose push loses its surface and runs on (cosmos.execution.lost_push): not settled."""

from __future__ import annotations

import numpy as np

from cosmos.execution.monitor import SegmentMonitor, Snapshot, Verdict
from cosmos.lang import compile_program
from cosmos.workcell import fixture_frames

DT_S = 0.004
DOWN_SPEED_MPS = 0.01
RAN_ON_M = 0.001
"""docs/language.md: a hold whose tool runs on 1 mm along its push has lost its surface."""


def _hold_monitor() -> tuple[SegmentMonitor, np.ndarray]:
    plan = compile_program("CONTACT DOWN FORCE 8 N\n", "c.cos", fixture_frames())
    (hold,) = [s for s in plan.segments if s.kind.value == "contact_hold"]
    start = np.array([0.6, 0.15, 0.2578])
    goal = (start.copy(), np.diag([1.0, -1.0, -1.0]))
    return SegmentMonitor(hold, 0.0, start, 0.0, start, None, goal, lambda: ""), start


def test_a_push_running_on_at_its_force_is_not_settled() -> None:
    """Catches "force settled" (or "contact held") told of a peg still falling down the bore: the
    wrist reads the bore's wall rubbing the peg, which can sit within the 0.8 N tolerance of an
    8 N push for the 0.2 s the settling takes. Running on 40 mm at 10 mm/s with the push exactly at
    FORCE, the hold never ends; at rest on the bottom it settles 0.2 s later, as at a first touch."""
    monitor, start = _hold_monitor()
    wrench = np.array([0.0, 0.0, -8.0, 0.0, 0.0, 0.0])  # the tool pushes 8 N down: on its setpoint
    rotation, velocity = np.diag([1.0, -1.0, -1.0]), np.array([0.0, 0.0, -DOWN_SPEED_MPS, 0.0, 0.0, 0.0])
    t, position = 0.0, start.copy()
    while t < 4.0:  # 40 mm, past the 3 s bound counted from the touch
        t += DT_S
        position = start - np.array([0.0, 0.0, DOWN_SPEED_MPS * t])
        assert monitor.check(Snapshot(t, position, rotation, velocity, wrench)) is None, f"ended at {t:.2f} s"
    landed, outcome = t, None
    while outcome is None and t < landed + 1.0:  # at rest on the bottom, at FORCE
        t += DT_S
        outcome = monitor.check(Snapshot(t, position, rotation, np.zeros(6), wrench))
    assert outcome is not None and outcome.verdict is Verdict.DONE and outcome.reason == "force settled"
    assert 0.2 - 1e-9 <= t - landed <= 0.2 + RAN_ON_M / DOWN_SPEED_MPS + 2 * DT_S


def test_a_hold_running_on_touching_nothing_fails_lost_contact() -> None:
    """Catches a CONTACT's hold pushing through free air: the new user's SPEED 100 mm/s CONTACT UP
    took its tool's inertia for a touch, and its hold pushed the tool 606 mm up, 7.2 s, until the
    path deviation stopped it. With the wrist reading nothing (under the 2 N touch threshold) and
    the tool running on down its push at 84 mm/s, the hold fails "lost contact" once it has run on
    LOST_CONTACT_M (15 mm, within a sample), whatever the 3 s bound. And the bore's wall rubbing a
    falling peg (6 N across the push, 2 N along it) is contact: that run is not cut short."""
    speed = 0.084
    rotation, velocity = np.diag([1.0, -1.0, -1.0]), np.array([0.0, 0.0, -speed, 0.0, 0.0, 0.0])
    for wrench, lost in ((np.zeros(6), True), (np.array([0.0, -6.0, -2.0, 0.0, 0.0, 0.0]), False)):
        monitor, start = _hold_monitor()
        t, outcome, position = 0.0, None, start.copy()
        while outcome is None and t < 0.5:  # 42 mm
            t += DT_S
            position = start - np.array([0.0, 0.0, speed * t])
            outcome = monitor.check(Snapshot(t, position, rotation, velocity, wrench))
        if not lost:
            assert outcome is None, outcome
            continue
        assert outcome is not None and outcome.verdict is Verdict.FAILED, outcome
        assert outcome.reason.startswith("lost contact: the tool ran on"), outcome.reason
        assert 0.015 < start[2] - position[2] <= 0.015 + speed * DT_S
