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

from tests.run.run_support import PROGRAMS, ProgramRun, read_run, write_program

APPROACH = """\
MOVE TO table + (0, 0, 25 mm)
CONTACT DOWN FORCE 12 N SPEED 10 mm/s
"""
SPEED_M_S = 0.010


def _run_varied(program: Path, values: dict[str, float]) -> ProgramRun:
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates
    from cosmos.sweep.variation import WorkcellVariation

    log_path = program.with_suffix(".mcap")
    variation = WorkcellVariation.from_values(values)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        returncode = run_program(program, log_path, Rates(), 0, variation=variation)
    return read_run(program, log_path, returncode, out.getvalue(), err.getvalue())


@pytest.mark.parametrize(("payload_kg", "seed"), [(0.34, 556745865), (0.5, 0)])
def test_contact_approach_with_an_unknown_payload_cruises_at_its_speed(
    tmp_path: Path, payload_kg: float, seed: int
) -> None:
    """Catches an untared payload's weight taken for a push: the approach crawled at 44 % of its SPEED."""
    program = write_program(tmp_path, "approach", APPROACH)
    run = _run_varied(program, {"payload": payload_kg, "seed": float(seed)})
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


def test_a_lift_out_of_the_bore_on_a_heavier_arm_stops_at_its_goal(tmp_path: Path) -> None:
    """Catches the cruise's integral cruising on past the goal. Run 8 of a sweep of peg_in_hole.cos
    (model_error, payload, friction varied): the bore held the peg back while the integral waited
    for the rubbing to stop; let go 7 mm before the goal, the integral grew to carry the heavier
    arm and the unknown 0.47 kg at SPEED, and past the goal (eq. 21's limit binding again there)
    held it on: the MOVE BY 30 mm ran 38 mm past its goal and failed there."""
    program = tmp_path / "peg_in_hole.cos"
    program.write_text((PROGRAMS / "peg_in_hole.cos").read_text(encoding="utf-8"), encoding="utf-8")
    values = {"model_error": 0.0806175, "payload": 0.4694335, "friction": 0.2300290, "seed": 3031610183.0}
    run = _run_varied(program, values)
    assert run.returncode == 0, run.describe()
    line = run.line_of("MOVE BY (0, 0, 30 mm)")
    on = run.log.state.line == line
    z = run.log.state.x[on, 2]
    assert z.max() - (z[0] + 0.030) < 0.003
