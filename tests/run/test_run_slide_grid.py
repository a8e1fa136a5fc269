"""Contact held while sliding (issue 14, item 5): representative cases of tests/run/slide_grid.py.

The whole grid (54 cases) runs with ``python tests/run/slide_grid.py``; its figures
are in the README. Here: a heavy slow diagonal slide and a fast one, which hold,
and the worst case the grid finds, light and fast, which does not yet (strict
xfail with the measured cause, so that a fix shows).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from run_support import BOTH_PLANTS, FLAT_END
from slide_grid import Case, run_case


def test_heavy_slow_diagonal_slide_holds_its_push(tmp_path: Path) -> None:
    """30 N, 5 mm/s, world diagonal: the push never below 50 % of 30 N and within 15 % for 95 % of
    the slide, at 80 % of SPEED or more. Catches a slide that loses or spikes its contact, or
    crawls, where the contact is firm."""
    result = run_case(Case(30.0, 5.0, "diagonal", "world"), tmp_path)
    assert result.ok, result


@pytest.mark.xfail(
    strict=True,
    reason=FLAT_END + "on both plants at 12 N and 50 mm/s along -Y the push's lowest is 0.4 % of its "
    "setpoint and 75.7 % of the slide is within 15 % (ideal plant)",
)
@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_fast_slide_in_world_y_holds_its_push(tmp_path: Path, ideal: bool) -> None:
    """12 N, 50 mm/s, -Y: the same bar at the grid's top speed. Catches the tool contact
    creeping out of the table while it slides fast (with the pyramidal friction cone its
    push fell to 0.1-6 % of the setpoint at 50 mm/s, every case)."""
    result = run_case(Case(12.0, 50.0, "-Y", "world"), tmp_path, ideal)
    assert result.ok, result


@pytest.mark.xfail(
    strict=True,
    reason=(
        "physics: at 5 N and 50 mm/s the tool's soft contact (solref 0.18 s, elliptic cone) "
        "still creeps out of the table while it slides: the contact's damping on the sliding "
        "velocity lifts the tip (0.9 mm at 50 mm/s with solref 0.2 s), the push at 5 N cannot "
        "hold it in, and the contact drops for milliseconds (push down to 3-4 % of its setpoint; "
        "71-74 % of the slide within 15 %). A lower contact damping (solref -27.7 -4) keeps it in "
        "(lowest 53-65 %) but the push rings (44-82 % within 15 %), the force axis does not "
        "settle (6.1-8.9 N at 10 N) and the stiff peg no longer jams (README)"
    ),
)
def test_light_fast_slide_holds_its_push(tmp_path: Path) -> None:
    """5 N, 50 mm/s, +X: the worst case of the grid, judged on the same bar."""
    result = run_case(Case(5.0, 50.0, "+X", "world"), tmp_path)
    assert result.ok, result
