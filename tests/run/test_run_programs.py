"""Every shipped program (programs/*.cos) runs through ``cosmos run`` with exit status 0.

Each ran once through the command line (see conftest.py); its log must be
complete, every statement that started must have closed with ``done`` or
``stopped``, and nothing may have failed. The procedure-and-repeat program is
also checked for doing what it says: three touches of the table, 20 mm apart.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from run_support import PROGRAMS, SHIPPED, TABLE_POINT_M, TABLE_TOP_Z_M, ProgramRun

REQUIRED = {"hello.cos", "contact_slide.cos", "peg_in_hole.cos", "comply_slope.cos", "procedures.cos"}


def test_the_required_programs_are_shipped() -> None:
    """Issue 5 names these programs; a procedure-and-repeat program is procedures.cos."""
    assert REQUIRED <= set(SHIPPED), sorted(SHIPPED)
    source = (PROGRAMS / "procedures.cos").read_text(encoding="utf-8").upper()
    assert "PROC " in source and "REPEAT " in source


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_program_runs(name: str, shipped_run: Callable[[str], ProgramRun]) -> None:
    """Exit 0, the log's path printed, a complete log, every statement closed, none failed
    (but where a TRY recovered it)."""
    run = shipped_run(name)
    assert run.returncode == 0, run.describe()
    assert "Traceback" not in run.stderr
    assert f"log: {run.log.path}" in run.stdout.splitlines(), run.stdout
    assert not run.log.truncated
    assert run.log.source == run.source
    events = run.log.events
    # a failure is allowed only where a TRY's ON FAIL part takes it over (the next event)
    recovered = {
        i for i, e in enumerate(events[:-1]) if e.kind == "failed" and events[i + 1].kind == "recovery"
    }
    assert len(run.events("failed")) == len(recovered), run.describe()
    open_line = None
    for index, event in enumerate(events):
        if event.kind == "start":
            assert open_line is None, f"line {event.line} started inside line {open_line}"
            open_line = event.line
        elif event.kind in ("done", "stopped") or index in recovered:
            assert event.line == open_line, run.describe()
            open_line = None
    assert open_line is None, f"line {open_line} never closed\n{run.describe()}"
    assert run.log.events[-1].kind in ("done", "stopped")


def test_procedures_touch_the_table_three_times(shipped_run: Callable[[str], ProgramRun]) -> None:
    """The PROC inside REPEAT 3 touches the table at three points 20 mm apart along x."""
    run = shipped_run("procedures.cos")
    contact_line = run.line_of("CONTACT DOWN")
    touches = run.events("contact", contact_line)
    assert len(touches) == 3, run.describe()
    state = run.log.state
    at = [int(np.searchsorted(state.t, e.t)) for e in touches]
    points = state.x[at]
    assert np.all(np.abs(points[:, 2] - TABLE_TOP_Z_M) < 1e-3), points
    start = TABLE_POINT_M + np.array([-0.020, 0.0, 0.0])
    expected_x = start[0] + np.array([0.0, 0.020, 0.040])
    assert points[:, 0] == pytest.approx(expected_x, abs=1.5e-3)
    assert points[:, 1] == pytest.approx(np.full(3, start[1]), abs=1.5e-3)
