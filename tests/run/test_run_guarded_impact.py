"""A guarded MOVE's impact: at the default speed it hit the table at 174 N and was "stopped" (issue 14).

``MOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N`` from 50 mm over the table, at the default
100 mm/s, fired its UNTIL at 5.7 N and the wrist then read 174.2 N 4 ms later while the arm
braked (docs/language.md's own UNTIL example: 209.1 N); the statement's force limit is
2 x 5 + 30 = 40 N, the sensor's rating 130 N. A guarded motion on a force now lands on a surface
its workcell model knows as a CONTACT's approach does (cosmos.runtime.landing_zone). Judged by the
documented limit (docs/language.md, "Protective stops"), on the wrist samples of the log from the
statement's last 0.2 s to 0.1 s after its stop, on the table (cushioned) and the hole fixture's
steel top face.
"""

from __future__ import annotations

import numpy as np
import pytest
from run_support import ProgramRun, run_in_process, write_program

PROGRAMS = {
    "table": "MOVE TO table + (0, 0, 50 mm)\nMOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N\nWAIT 0.3 s\n",
    "hole_face": "MOVE TO hole + (0, 40 mm, 30 mm)\nMOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N\nWAIT 0.3 s\n",
}
LIMIT_N = 2.0 * 5.0 + 30.0
"""The guarded statement's documented force limit: twice its threshold plus 30 N."""


@pytest.fixture(scope="module", params=sorted(PROGRAMS))
def guarded_run(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The guarded MOVE at the default speed onto ``request.param``."""
    directory = tmp_path_factory.mktemp(f"guarded_{request.param}")
    program = write_program(directory, request.param, PROGRAMS[request.param])
    return run_in_process(program, directory / f"{request.param}.mcap")


def test_a_guarded_move_at_its_default_speed_lands_within_its_force_limit(guarded_run: ProgramRun) -> None:
    """Stopped on its UNTIL, and the wrist's peak around the stop is within 2 x 5 + 30 N (was 174 N)."""
    assert guarded_run.returncode == 0, guarded_run.describe()
    line = guarded_run.line_of("UNTIL FORCE")
    stopped = guarded_run.events("stopped", line)
    assert len(stopped) == 1, guarded_run.describe()
    state = guarded_run.log.state
    around = (state.t >= stopped[0].t - 0.2) & (state.t <= stopped[0].t + 0.1)
    peak = float(np.max(np.linalg.norm(state.wrench[around, :3], axis=1)))
    assert peak <= LIMIT_N, f"peak {peak:.1f} N around the stop at {stopped[0].t:.3f} s"
