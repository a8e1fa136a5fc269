"""IF and WHILE decided on what the arm senses (issue 22, "Must show").

The table cannot be moved by a program, so the two runs differ only in how high
above the table the CONTACT starts (20 mm or 60 mm), which is the same as a table
40 mm higher or lower under the same start. ``CONTACT DOWN ... UNTIL DISTANCE >
40 mm`` touches and presses 10 N from 20 mm up; from 60 mm its UNTIL ends it in
free air. ``IF FORCE Z < -5 N`` must then take the IF branch in the first run and
the ELSE branch in the second, and the log must say so with the value read,
which is checked against the wrist sensor's own samples in the log.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from run_support import TABLE_TOP_Z_M, ProgramRun, run_in_process, write_program

TOUCH = """\
SPEED 0.25 m/s
MOVE TO table + (0, 0, {start})
CONTACT DOWN FORCE 10 N UNTIL DISTANCE > 40 mm TIMEOUT 5 s
IF FORCE Z < -5 N
  MOVE BY (0, 0, 50 mm)
ELSE
  MOVE BY (0, 0, 40 mm)
END
WHILE POSITION Z < -25 mm IN table MAX 10
  MOVE BY (0, 0, -10 mm)
END
"""
IF_LINE, THEN_LINE, ELSE_LINE, WHILE_LINE, BODY_LINE = 4, 5, 7, 9, 10
READ = re.compile(r"FORCE Z < -5 N: read (-?[0-9.e+-]+) N")


def _run(directory_factory: pytest.TempPathFactory, name: str, source: str) -> ProgramRun:
    directory = directory_factory.mktemp(name)
    return run_in_process(write_program(directory, name, source), directory / f"{name}.mcap")


@pytest.fixture(scope="module")
def near(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The CONTACT starts 20 mm above the table: it touches."""
    return _run(tmp_path_factory, "near", TOUCH.format(start="20 mm"))


@pytest.fixture(scope="module")
def far(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The CONTACT starts 60 mm above the table: its UNTIL stops it 20 mm short."""
    return _run(tmp_path_factory, "far", TOUCH.format(start="60 mm"))


def _decision(run: ProgramRun) -> tuple[str, float]:
    events = run.events("decision", IF_LINE)
    assert len(events) == 1, run.describe()
    match = READ.search(events[0].reason)
    assert match, events[0].reason
    return events[0].reason, float(match[1])


def _sensed_z(run: ProgramRun, t: float) -> float:
    """The wrist's force on world z in the last state samples up to ``t`` (mean of 5) [N]."""
    state = run.log.state
    before = np.flatnonzero(state.t <= t + 1e-9)[-5:]
    return float(state.wrench[before, 2].mean())


def test_each_run_takes_its_branch(near: ProgramRun, far: ProgramRun) -> None:
    """Near: the IF branch ran and not the ELSE one; far: the reverse. The decision event names
    the branch. Catches a decision read at the wrong time or a branch that is not the one named."""
    for run in (near, far):
        assert run.returncode == 0, run.describe()
    near_reason, _ = _decision(near)
    far_reason, _ = _decision(far)
    assert "holds: runs the IF branch" in near_reason
    assert "does not hold: runs the ELSE branch" in far_reason
    assert near.events("done", THEN_LINE) and not near.events(line=ELSE_LINE)
    assert far.events("done", ELSE_LINE) and not far.events(line=THEN_LINE)


def test_the_value_read_is_what_the_wrist_sensed(near: ProgramRun, far: ProgramRun) -> None:
    """The force the decision logged agrees with the logged wrench at that time (within the
    sensor's noise), pressing about 10 N in the near run and about 0 N in the far one."""
    for run, expected in ((near, -10.0), (far, 0.0)):
        _, value = _decision(run)
        t = run.events("decision", IF_LINE)[0].t
        assert value == pytest.approx(_sensed_z(run, t), abs=1.0), run.describe()
        assert value == pytest.approx(expected, abs=2.0), run.describe()


def test_while_runs_until_its_condition_fails(near: ProgramRun, far: ProgramRun) -> None:
    """The WHILE steps 10 mm down while the tool is over 25 mm above the table (the table frame's
    Z points into the table, so that is POSITION Z < -25 mm IN table): its number of passes is
    the one the logged height at its start gives, and it ends at most 25 mm up. Catches a
    position read in the wrong frame or a loop that miscounts its passes."""
    for run in (near, far):
        decisions = run.events("decision", WHILE_LINE)
        start_t = decisions[0].t
        state = run.log.state
        z0 = state.x[np.flatnonzero(state.t <= start_t + 1e-9)[-1], 2] - TABLE_TOP_Z_M
        passes = math.ceil((z0 - 0.025) / 0.010)
        assert len(run.events("done", BODY_LINE)) == passes, run.describe()
        assert [e.reason.endswith(f"pass {i + 1}") for i, e in enumerate(decisions[:-1])] == [True] * passes
        assert f"ends after {passes} passes" in decisions[-1].reason
        assert state.x[-1, 2] - TABLE_TOP_Z_M <= 0.025 + 1e-3


def test_while_past_its_bound_fails(tmp_path_factory: pytest.TempPathFactory) -> None:
    """A WHILE that still holds after MAX passes ends the program, naming the WHILE and its bound.
    Catches an unbounded loop."""
    source = (
        "MOVE TO table + (0, 0, 50 mm)\nWHILE POSITION Z < 0 m IN table MAX 2\n  MOVE BY (0, 0, 5 mm)\nEND\n"
    )
    run = _run(tmp_path_factory, "unbounded", source)
    assert run.returncode == 1, run.describe()
    assert len(run.events("done", 3)) == 2
    failed = run.events("failed", 2)
    assert failed and "still holds after 2 passes (MAX 2)" in failed[0].reason, run.describe()
    assert "WHILE" in run.stderr and "MAX 2" in run.stderr
