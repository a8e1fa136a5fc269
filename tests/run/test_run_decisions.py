"""IF and WHILE decided on what the arm senses (issue 22, "Must show").

Two runs of one program differ only in the table's height: the real table is
where the program's ``table`` frame says, or 40 mm lower (``cosmos run --vary
'table.z=-40 mm'``: the workcell changes, the program's frames do not).
``CONTACT DOWN ... UNTIL DISTANCE > 40 mm`` starts 20 mm above the nominal table:
it touches and presses 10 N on the nominal table, and on the lowered one its
UNTIL ends it in free air 20 mm short. ``IF FORCE Z < -5 N`` must then take the
IF branch in the first run and the ELSE branch in the second, and the log must
say so with the value read, which is checked against the wrist sensor's own
samples in the log.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
from typing import NoReturn

import numpy as np
import pytest
from run_support import TABLE_TOP_Z_M, ProgramRun, read_run, run_in_process, write_program

from cosmos import plan
from cosmos.commands.check import load_fixtures
from cosmos.errors import TaskFailure
from cosmos.execution.walker import PlanWalker, Senses
from cosmos.lang import compile_program

TOUCH = """\
SPEED 0.25 m/s
MOVE TO table + (0, 0, 20 mm)
CONTACT DOWN FORCE 10 N UNTIL DISTANCE > 40 mm TIMEOUT 5 s
IF FORCE Z < -5 N
  MOVE BY (0, 0, 50 mm)
ELSE
  MOVE BY (0, 0, 70 mm)
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


def _run_on_table(directory_factory: pytest.TempPathFactory, name: str, table_z_m: float) -> ProgramRun:
    """TOUCH run in-process with the real table moved ``table_z_m`` along world z."""
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates
    from cosmos.sweep.variation import WorkcellVariation

    directory = directory_factory.mktemp(name)
    program = write_program(directory, name, TOUCH)
    log_path = directory / f"{name}.mcap"
    variation = WorkcellVariation.from_values({"table.z": table_z_m})
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        returncode = run_program(program, log_path, Rates(), 0, variation=variation)
    return read_run(program, log_path, returncode, out.getvalue(), err.getvalue())


@pytest.fixture(scope="module")
def near(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The table where the program's frame says: the CONTACT touches it."""
    return _run_on_table(tmp_path_factory, "near", 0.0)


@pytest.fixture(scope="module")
def far(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The table 40 mm lower: the CONTACT's UNTIL stops it 20 mm short."""
    return _run_on_table(tmp_path_factory, "far", -0.040)


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
    assert near.events("contact", 3) and not far.events("contact", 3), "one table is touched, one not"
    assert far.events("stopped", 3), far.describe()
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
        assert decisions[-1].reason.endswith(f"ends after {passes} pass" + ("" if passes == 1 else "es"))
        assert state.x[-1, 2] - TABLE_TOP_Z_M <= 0.025 + 1e-3


def test_while_past_its_bound_fails(tmp_path_factory: pytest.TempPathFactory) -> None:
    """A WHILE that still holds after MAX passes ends the program, naming the WHILE, its bound
    and the value it read last. Catches an unbounded loop, and the message headed by the
    condition's first word ("WHILE POSITION still holds after 2 passes") without the reading."""
    source = (
        "MOVE TO table + (0, 0, 50 mm)\nWHILE POSITION Z < 0 m IN table MAX 2\n  MOVE BY (0, 0, 5 mm)\nEND\n"
    )
    run = _run(tmp_path_factory, "unbounded", source)
    assert run.returncode == 1, run.describe()
    assert len(run.events("done", 3)) == 2
    failed = run.events("failed", 2)
    assert failed and "still holds after 2 passes (MAX 2)" in failed[0].reason, run.describe()
    assert "WHILE" in run.stderr and "MAX 2" in run.stderr
    assert re.search(
        r":2:1: WHILE still holds after 2 passes \(MAX 2\): POSITION Z < 0 m: read -\d+\.\d mm", run.stderr
    )


# ------------------------------------------- the walker alone, on a runner that records


class _Interrupted(TaskFailure):
    """Stands for the executor's interruption (Ctrl-C)."""


class _Recorder:
    """A runner whose statements end as a script says; it records what ran and the events."""

    def __init__(self, endings: dict[int, list[str]], force_z: float = 0.0):
        self.endings = (
            endings  # line -> endings of its runs in turn: "done", "stopped", "failed", "interrupted"
        )
        self.ran: list[int] = []
        self.events: list[tuple[str, int]] = []
        self.force_z = force_z

    def run_statement(self, segments: list[plan.Segment]) -> bool:
        line = segments[0].line
        self.ran.append(line)
        ending = self.endings.get(line, ["done"]).pop(0) if self.endings.get(line) else "done"
        if ending == "failed":
            self.events.append(("failed", line))
            raise TaskFailure(f"line {line} failed", segments[0].span, None)
        if ending == "interrupted":
            raise _Interrupted("interrupted", segments[0].span, None)
        return ending == "stopped"

    def scene_step(self, step: plan.AddObstacle | plan.RemoveObstacle) -> None:
        raise AssertionError("no scene steps here")

    def senses(self) -> Senses:
        return Senses(np.array([0.0, 0.0, self.force_z]), np.zeros(3), np.zeros(3))

    def note(self, kind: str, step: plan.Step, reason: str) -> None:
        self.events.append((kind, step.line))

    def fail(self, step: plan.Step, reason: str) -> NoReturn:
        self.events.append(("failed", step.line))
        raise TaskFailure(reason, step.span, None)

    def recoverable(self, failure: TaskFailure) -> bool:
        return not isinstance(failure, _Interrupted)


def _walk(source: str, runner: _Recorder) -> None:
    PlanWalker(runner).walk(compile_program(source, "walk.cos", load_fixtures()).steps)


def test_last_stopped_reads_how_the_statement_before_ended() -> None:
    """LAST STOPPED holds after a statement its UNTIL ended, not after one that was done.
    Catches an ending not recorded, or read from the wrong statement."""
    source = "WAIT 1 s\nIF LAST STOPPED\n  WAIT 2 s\nELSE\n  WAIT 3 s\nEND\n"
    stopped, done = _Recorder({1: ["stopped"]}), _Recorder({})
    _walk(source, stopped)
    _walk(source, done)
    assert stopped.ran == [1, 3] and done.ran == [1, 5]


def test_an_inner_retry_runs_the_inner_try_and_the_outer_handler_takes_what_is_left() -> None:
    """RETRY runs the block of the TRY whose ON FAIL part it is in; when its count is used up (the
    handler having run again first) the failure goes to the enclosing TRY's handler, where LAST
    FAILED holds. Catches a RETRY caught by the wrong TRY, or retries beyond the count."""
    source = (
        "TRY\n"  # 1
        "  TRY\n"  # 2
        "    WAIT 1 s\n"  # 3
        "  ON FAIL\n"  # 4
        "    WAIT 2 s\n"  # 5
        "    RETRY 1\n"  # 6
        "  END\n"  # 7
        "ON FAIL\n"  # 8
        "  IF LAST FAILED\n"  # 9
        "    WAIT 3 s\n"  # 10
        "  END\n"  # 11
        "END\n"  # 12
        "WAIT 4 s\n"  # 13
    )
    runner = _Recorder({3: ["failed", "failed"]})
    _walk(source, runner)
    assert runner.ran == [3, 5, 3, 5, 10, 13]
    assert runner.events == [
        ("failed", 3),
        ("recovery", 2),
        ("retry", 6),
        ("failed", 3),
        ("recovery", 2),
        ("failed", 6),  # RETRY 1 used up: the inner TRY fails at its RETRY ...
        ("recovery", 1),  # ... and the outer ON FAIL takes that over
        ("decision", 9),
    ]


def test_an_interruption_is_never_taken_over_by_a_try() -> None:
    """Ctrl-C inside TRY ends the program: the handler does not run."""
    runner = _Recorder({2: ["interrupted"]})
    with pytest.raises(_Interrupted):
        _walk("TRY\n  WAIT 1 s\nON FAIL\n  WAIT 2 s\nEND\n", runner)
    assert runner.ran == [2] and not runner.events
