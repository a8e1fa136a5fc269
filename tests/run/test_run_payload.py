"""A payload the controller does not know: the cell's tare keeps its weight from reading as a push.

A sweep's ``payload`` (docs/sweep.md) hangs a mass on the tool that the controller's tool
model lacks. The cell tares its wrist sensor with the tool as mounted (cosmos/realism/tare.py),
so at the start pose the payload reads nothing; before, its weight read as a steady push, the
cruise's integral held off (cosmos/osc/cruise_speed.py) and a CONTACT's approach at SPEED
10 mm/s cruised at 4.4 mm/s with 0.34 kg (sweep run 10 of a user's program, seed 556745865).
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest

from tests.run.run_support import ProgramRun, read_run, write_program

APPROACH = """\
MOVE TO table + (0, 0, 25 mm)
CONTACT DOWN FORCE 12 N SPEED 10 mm/s
"""
SPEED_M_S = 0.010


def _run_with_payload(directory: Path, payload_kg: float, seed: int) -> ProgramRun:
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates
    from cosmos.sweep.variation import WorkcellVariation

    program = write_program(directory, "approach", APPROACH)
    log_path = directory / "approach.mcap"
    variation = WorkcellVariation.from_values({"payload": payload_kg, "seed": float(seed)})
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        returncode = run_program(program, log_path, Rates(), 0, variation=variation)
    return read_run(program, log_path, returncode, out.getvalue(), err.getvalue())


@pytest.mark.parametrize(("payload_kg", "seed"), [(0.34, 556745865), (0.5, 0)])
def test_contact_approach_with_an_unknown_payload_cruises_at_its_speed(
    tmp_path: Path, payload_kg: float, seed: int
) -> None:
    """Catches an untared payload's weight taken for a push: the approach crawled at 44 % of its SPEED."""
    run = _run_with_payload(tmp_path, payload_kg, seed)
    assert run.returncode == 0, run.describe()
    (approach,) = run.segments("contact_approach")
    state = run.log.state
    on = state.segment == approach.segment
    t, x = state.t[on], state.x[on]
    speed = np.linalg.norm(x[5:] - x[:-5], axis=1) / (t[5:] - t[:-5])
    cruise = speed[len(speed) // 4 : 3 * len(speed) // 4]  # between the start's ramp and the touch
    assert np.median(cruise) == pytest.approx(SPEED_M_S, rel=0.1), run.describe()
    touch = run.events("contact")[0]
    assert "touched" in touch.reason
    assert x[-1, 2] < 0.2 + 0.0015  # touched at the table top (200 mm), not in the air
