"""A segment with a TIMEOUT and no UNTIL is judged in one call a tick: its ending, then its TIMEOUT."""

from __future__ import annotations

import numpy as np

from cosmos.execution.monitor import SegmentMonitor, Snapshot, Verdict
from cosmos.lang import compile_program
from cosmos.workcell import fixture_frames


def test_a_contact_without_until_times_out_at_its_timeout_tick() -> None:
    """A CONTACT's approach that touches nothing, TIMEOUT 50 ms: its judge (the ending and the
    TIMEOUT, one call) fails "found no contact within 0.05 s" at the tick 50 ms after the statement
    began, as :meth:`SegmentMonitor.check` does, and not a tick before. Catches the one-call judge
    leaving the TIMEOUT out (the approach ran on to its 300 mm), or judging it a tick early."""
    plan = compile_program("CONTACT DOWN FORCE 5 N TIMEOUT 50 ms\n", "c.cos", fixture_frames())
    approach = plan.segments[0]
    start = np.array([0.6, -0.15, 0.3])
    found = []
    for ask in ("judge", "check"):
        monitor = SegmentMonitor(approach, 0.0, start, 0.0, start, None, (start, np.eye(3)), lambda: "")
        assert ask == "check" or monitor.judge != monitor.check  # one call: not check's
        position = start.copy()
        snap = Snapshot(0.0, position, np.eye(3), np.array([0.0, 0.0, -0.02, 0.0, 0.0, 0.0]), np.zeros(6))
        for tick in range(1, 100):
            snap.t_s = tick * 0.001
            position[2] = start[2] - 0.02 * snap.t_s  # going down at 20 mm/s, touching nothing
            outcome = getattr(monitor, ask)(snap)
            if outcome is not None:
                found.append((tick, outcome.verdict, outcome.reason))
                break
    assert found == [(50, Verdict.FAILED, "found no contact within 0.05 s")] * 2
