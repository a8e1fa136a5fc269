"""A MOVE's TIMEOUT and UNTIL are judged on its last leg too (the monitor's one-call judge there).

The monitor judges the last leg of a segment with no UNTIL and no TIMEOUT by its own ending
alone; these runs check that a TIMEOUT or an UNTIL still ends a MOVE at the tick it is due,
against the times and forces the log records.
"""

from __future__ import annotations

import pytest
from run_support import ProgramRun, run_in_process, write_program

SLOW_MOVE = """\
MOVE BY (0, 0, 60 mm) SPEED 20 mm/s TIMEOUT 0.4 s
"""

GUARDED_MOVE = """\
SPEED 0.25 m/s
MOVE TO table + (0, 0, 20 mm)
MOVE BY (0, 0, -60 mm) SPEED 40 mm/s UNTIL FORCE > 3 N
"""


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, ProgramRun]:
    directory = tmp_path_factory.mktemp("last_leg")
    return {
        name: run_in_process(write_program(directory, name, text), directory / f"{name}.mcap")
        for name, text in (("slow", SLOW_MOVE), ("guarded", GUARDED_MOVE))
    }


def test_a_moves_timeout_ends_it_when_due(runs: dict[str, ProgramRun]) -> None:
    """A 60 mm MOVE at 20 mm/s (3 s) with TIMEOUT 0.4 s fails 0.4 s after it started, to the tick.

    Catches the last leg judged by its arrival alone although a TIMEOUT is set: the MOVE ran
    its 3 s and was done."""
    run = runs["slow"]
    assert run.returncode == 1, run.describe()
    (start,) = run.events("start", 1)
    (failed,) = run.events("failed", 1)
    assert "timed out after 0.4 s" in failed.reason, failed.reason
    assert abs((failed.t - start.t) - 0.4) <= 1.5e-3, f"failed {failed.t - start.t:.4f} s after the start"


def test_a_moves_until_ends_it_on_the_table(runs: dict[str, ProgramRun]) -> None:
    """The guarded MOVE stops at its first state sample with more than 3 N pushing on the table.

    Catches the last leg judged by its arrival alone although an UNTIL is set: the MOVE pressed
    on into the table until a protective stop."""
    run = runs["guarded"]
    assert run.returncode == 0, run.describe()
    line = run.line_of("UNTIL FORCE")
    (stopped,) = run.events("stopped", line)
    state = run.log.state
    during = (state.t > run.events("start", line)[0].t) & (state.t <= stopped.t + 1e-9)
    pushes = -state.wrench[during, 2]  # the wrench is what the tool applies: pushing down, -z
    assert pushes.max() > 3.0, f"stopped at most {pushes.max():.2f} N"
