"""A guarded MOVE: ``MOVE ... UNTIL FORCE > 4 N`` toward the table stops on it (issue 5, "Must show").

A statement stopped by its UNTIL counts as done (event ``stopped``, exit 0) and
the arm holds where it stopped. Judged against the table top's height, z = 0.20 m.
"""

from __future__ import annotations

import numpy as np
import pytest
from run_support import TABLE_TOP_Z_M, ProgramRun, run_in_process, write_program

GUARDED_PROGRAM = """\
SPEED 0.25 m/s
MOVE TO table + (0, 0, 30 mm)
MOVE BY (0, 0, -100 mm) SPEED 50 mm/s UNTIL FORCE > 4 N
WAIT 0.5 s
"""


@pytest.fixture(scope="module")
def guarded_run(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """MOVE BY 100 mm down from 30 mm above the table, guarded by FORCE > 4 N; then WAIT."""
    directory = tmp_path_factory.mktemp("guarded")
    program = write_program(directory, "guarded", GUARDED_PROGRAM)
    return run_in_process(program, directory / "guarded.mcap")


def test_guarded_move_is_stopped_with_success(guarded_run: ProgramRun) -> None:
    """Exit 0; the MOVE closes with ``stopped`` (not done: 100 mm would be 70 mm into the table)."""
    assert guarded_run.returncode == 0, guarded_run.describe()
    line = guarded_run.line_of("UNTIL FORCE")
    closing = [e.kind for e in guarded_run.events(line=line) if e.kind in ("done", "stopped", "failed")]
    assert closing == ["stopped"], guarded_run.describe()
    assert not guarded_run.events("failed")


def test_guarded_move_stops_on_the_table(guarded_run: ProgramRun) -> None:
    """The tool point is within 2 mm of the table top when the MOVE stops, and stays there."""
    line = guarded_run.line_of("UNTIL FORCE")
    stopped = guarded_run.events("stopped", line)
    assert len(stopped) == 1, guarded_run.describe()
    state = guarded_run.log.state
    at_stop = int(np.searchsorted(state.t, stopped[0].t))
    z_at_stop_m = float(state.x[min(at_stop, len(state) - 1), 2])
    assert abs(z_at_stop_m - TABLE_TOP_Z_M) <= 2e-3, f"stopped at z = {z_at_stop_m * 1e3:.2f} mm"
    after = state.t >= stopped[0].t
    z_after_m = state.x[after, 2]
    assert np.all(np.abs(z_after_m - TABLE_TOP_Z_M) <= 2e-3), (
        f"held between z = {z_after_m.min() * 1e3:.2f} and {z_after_m.max() * 1e3:.2f} mm"
    )
