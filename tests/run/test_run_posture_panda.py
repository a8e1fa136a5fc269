"""POSTURE on the Panda: the seventh joint's null space moves the arm while the tool is held.

With the full six-axis task (no ORIENTATION FREE) the Panda keeps one dimension of self-motion
(eq. 28, 34): a POSTURE change must turn the joints by degrees while the tool, measured in the
log, stays within 1 mm (issue 16, "Posture"). Catches a posture torque that leaks into the task
(not through N^T), or a POSTURE home taken from the PUMA's six-joint home.
"""

from __future__ import annotations

import numpy as np
import pytest
from run_support import ProgramRun, run_in_process, samples_of, write_program

PROGRAM = """\
ROBOT panda
MOVE BY (0, 0, 30 mm)
POSTURE (-30 deg, 30 deg, 30 deg, -110 deg, 0 deg, 130 deg, 0 deg)
WAIT 2 s
POSTURE home
WAIT 2 s
"""


@pytest.fixture(scope="module")
def posture_run(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    directory = tmp_path_factory.mktemp("posture_panda")
    run = run_in_process(write_program(directory, "posture", PROGRAM), directory / "posture.mcap")
    assert run.returncode == 0, run.describe()
    return run


def test_posture_moves_the_joints_and_not_the_tool(posture_run: ProgramRun) -> None:
    waits = [s.segment for s in posture_run.segments("wait")]
    state = posture_run.log.state
    mask = samples_of(posture_run, waits)
    tool_mm = 1e3 * np.linalg.norm(state.x[mask] - state.x[mask][0], axis=1).max()
    swing_deg = np.degrees(np.ptp(state.q[mask], axis=0)).max()
    assert swing_deg > 10.0, f"the joints turned at most {swing_deg:.1f} deg"
    assert tool_mm < 1.0, f"the tool moved {tool_mm:.2f} mm"
    # POSTURE home brings the arm back towards its home (the first WAIT's start is near it).
    first, last = state.q[mask][0], state.q[mask][-1]
    middle = state.q[np.flatnonzero(samples_of(posture_run, waits[:1]))[-1]]
    assert np.linalg.norm(last - first) < 0.5 * np.linalg.norm(middle - first)
