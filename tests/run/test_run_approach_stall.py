"""A CONTACT's approach that stands short of its touch (cosmos.execution.approach_stall)."""

from __future__ import annotations

import contextlib
import io
from collections.abc import Callable
from pathlib import Path

import numpy as np
from run_support import write_program

from cosmos.commands.run import run_program
from cosmos.execution.approach_stall import LANDED_N
from cosmos.execution.closing import STALL_TIME_S
from cosmos.execution.monitor import Outcome, SegmentMonitor, Snapshot, Verdict
from cosmos.lang import compile_program
from cosmos.runlog import read_log
from cosmos.runtime.rates import Rates
from cosmos.sweep.variation import WorkcellVariation
from cosmos.workcell import fixture_frames

# Run 11 of `cosmos sweep P --runs 16 --vary friction='uniform(0.4,0.8)' --vary hole.x='normal(0,1mm)'`:
# the hole 2.48 mm along +x puts the peg's end on the chamfer's far side.
ON_THE_CHAMFER = {"friction": 0.7893013216289814, "hole.x": 0.0024784394107819976, "seed": 4118645239.0}
PROGRAM = """\
ROBOT panda
MOVE TO hole + (3 mm, -2 mm, 8 mm) SPEED 0.15 m/s
CONTACT DOWN FORCE 6 N SPEED 8 mm/s TIMEOUT 20 s
INSERT DOWN DEPTH 25 mm FORCE 12 N TIMEOUT 30 s
"""


def test_an_approach_resting_on_a_chamfer_below_the_touch_threshold_has_landed(tmp_path: Path) -> None:
    """Catches a CONTACT whose peg came to rest on the hole's chamfer pressing 1-1.5 N, under its
    2 N touch, and stood there: without a TIMEOUT it ran 1124 s of simulated time with no outcome
    (a sweep's worker never finished), with this one it failed "found no contact within 20 s".
    The log must show the tool at rest and pressing when the approach is judged landed, and the
    peg going in."""
    log = tmp_path / "chamfer.mcap"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = run_program(
            write_program(tmp_path, "chamfer", PROGRAM),
            log,
            Rates(),
            0,
            variation=WorkcellVariation.from_values(ON_THE_CHAMFER),
        )
    record = read_log(log)
    touched = [e for e in record.events if e.kind == "contact"]
    assert touched and "stopped against it" in touched[0].reason, [e.reason for e in record.events]
    state = record.state
    before = (state.line == 3) & (state.t > touched[0].t - 1.0) & (state.t <= touched[0].t)
    assert abs(state.v[before][:, 2]).max() < 0.002  # at rest along the approach for the last second
    assert -state.wrench[before][-1, 2] >= LANDED_N  # and pressing down
    assert code == 0, [e.reason for e in record.events if e.kind == "failed"]


def test_a_stopped_approach_pressing_nothing_fails_and_a_slow_one_is_not_stopped() -> None:
    """Catches the rule counting a 0.1 mm/s approach (SPEED's least) as stopped after 2 s (it
    covers 0.2 mm, under the 0.5 mm a goal motion must close), and an approach held back in the
    air (an obstacle's field on a link) counted as landed, or failed without its cause."""

    def approach(speed: str) -> tuple[Callable[[float, float, float], Outcome | None], np.ndarray]:
        plan = compile_program(f"CONTACT DOWN FORCE 6 N SPEED {speed}\n", "c.cos", fixture_frames())
        segment = plan.segments[0]
        start = np.array([0.6, 0.15, 0.3])
        goal = (start, np.diag([1.0, -1.0, -1.0]))
        monitor = SegmentMonitor(segment, 0.0, start, 0.0, start, None, goal, lambda: "held")

        def judge(push_n: float, travel_m: float, t_s: float) -> Outcome | None:
            position = start - np.array([0.0, 0.0, travel_m])  # down
            wrench = np.array([0.0, 0.0, -push_n, 0.0, 0.0, 0.0])
            return monitor.judge(Snapshot(t_s, position, goal[1], np.zeros(6), wrench))

        return judge, start

    slow, _ = approach("0.1 mm/s")
    for tick in range(10000):  # 0.1 mm/s for 10 s
        assert slow(0.0, 0.0001 * 0.001 * tick, 0.001 * tick) is None
    held, _ = approach("20 mm/s")
    assert held(0.1, 0.012, 1.0) is None
    assert held(0.1, 0.012, 1.0 + STALL_TIME_S - 0.01) is None
    assert held(0.1, 0.012, 1.0 + STALL_TIME_S) == Outcome(
        Verdict.FAILED, "stopped 12.0 mm along its approach without touching (0.10 N along it for 2 s): held"
    )
    far, _ = approach("20 mm/s")
    assert far(0.0, 0.2995, 4.0) == Outcome(Verdict.FAILED, "found no contact within 300 mm")
