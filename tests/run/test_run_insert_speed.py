"""INSERT honours its SPEED along the insertion axis (issue 14, item 4), judged from the run's log.

The peg lands on the hole's chamfer 2 mm off its axis (as programs/peg_in_hole.cos),
then INSERT pushes 15 N down with the lateral axes compliant: where the chamfer
gives way the push would drive the peg into the hole at 55-80 mm/s (the damping
alone balances 15 N there). The insertion axis's speed must peak within 10 %
of its limit: SPEED's, or the documented default of 20 mm/s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from run_support import NOT_TRACED, run_in_process, samples_of, write_program

PROGRAM = """\
FRAME above = hole + (2 mm, 0, 80 mm)
SPEED 0.25 m/s
MOVE TO above
CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s
INSERT DOWN DEPTH 25 mm FORCE 15 N COMPLY X Y RX RY{speed} TIMEOUT 10 s
"""
DEFAULT_INSERT_SPEED_MPS = 0.020
"""docs/language.md: the insertion axis "is limited to 20 mm/s unless SPEED says otherwise"."""


PEAK_OVER = (
    "the INSERT's push peaks at 23.8 mm/s at its 20 mm/s, 19 % over (at SPEED 30 within 10 %), "
    "also without the friction asymmetry in the plant"
)


@pytest.mark.parametrize(
    ("speed_mmps", "ideal"),
    [
        pytest.param(
            None,
            False,
            id="default-realistic",
            marks=pytest.mark.xfail(strict=True, reason=NOT_TRACED + PEAK_OVER),
        ),
        pytest.param(None, True, id="default-ideal"),
        pytest.param(30.0, False, id="30-realistic"),
        pytest.param(30.0, True, id="30-ideal"),
    ],
)
def test_insert_peaks_within_ten_percent_of_its_speed(
    tmp_path: Path, speed_mmps: float | None, ideal: bool
) -> None:
    """The peak downward speed of the INSERT segment within 10 % of the limit, and the depth reached.
    Catches the push left uncapped on its force axis (55.6 mm/s at SPEED 10 mm/s, 80 mm/s in
    peg_in_hole.cos), and a cap so tight or so stuck in joint friction that the peg jams."""
    clause = "" if speed_mmps is None else f" SPEED {speed_mmps:g} mm/s"
    program = write_program(tmp_path, "insert_speed", PROGRAM.format(speed=clause))
    run = run_in_process(program, tmp_path / "insert_speed.mcap", ideal)
    assert run.returncode == 0, run.describe()
    limit = DEFAULT_INSERT_SPEED_MPS if speed_mmps is None else speed_mmps * 1e-3
    inserts = run.segments("insert")
    assert len(inserts) == 1 and inserts[0].speed_limit == pytest.approx(limit)
    down = -run.log.state.v[samples_of(run, [inserts[0].segment]), 2]
    assert down.max() <= 1.10 * limit, f"peak {down.max() * 1e3:.1f} mm/s, limit {limit * 1e3:g} mm/s"
    assert np.mean(down > 0.5 * limit) > 0.3, "the peg should travel near its speed, not crawl"
