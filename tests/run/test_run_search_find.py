"""After a SEARCH's find the INSERT goes in, from where users start their searches (issue 14).

Cases of tests/run/search_grid.py (a user's program: above the hole at a lateral error,
``CONTACT DOWN``, then ``INSERT DOWN ... SEARCH``), judged on the run's log: the INSERT done
with the tip at its DEPTH below the hole's mouth, on the hole's axis (the mouth and the axis as
tests/run/run_support.py writes them from docs/workcell.md), and the tool's tilt from the
orientation it started with after the find (the compliant rotations' window is 10 deg).
"""

from __future__ import annotations

import pytest
from run_support import BOTH_PLANTS
from search_grid import Case, run_case

WINDOW_DEG = 10.0
"""The compliant rotations' tilt window (docs/language.md, INSERT)."""
OVERSHOOT_DEG = 1.5
"""What the window's stop lets the tilt pass it by while the push tips the part (10.9 deg measured)."""
SENSOR_RATING_N = 130.0
"""The wrist sensor's rating (docs/language.md, "Limits")."""


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_a_lissajous_search_from_5_mm_off_goes_in(ideal: bool) -> None:
    """A user's ``SEARCH LISSAJOUS RADIUS 8 mm PITCH 3 mm`` from (-4 mm, 3 mm) off the hole, seed 0
    and the ideal plant. Catches the tilt window re-centred at the find on the peg its compliance
    had tipped to the window's edge (10.8 deg): the peg went on to 21 deg and wedged 4.9 mm into
    the hole ("jammed at depth 4.9 mm")."""
    result = run_case(Case(5.0, 143.13, "LISSAJOUS", 8.0, 3.0), 0, ideal)
    assert result.ok, result
    assert result.tilt_deg < WINDOW_DEG + OVERSHOOT_DEG, result


def test_a_found_peg_tipped_on_the_mouth_is_led_in() -> None:
    """A Panda's ``SEARCH SPIRAL RADIUS 12 mm PITCH 3 mm`` from 7.8 mm off, seed 2: the find leaves
    the peg tipped 10.8 deg on the mouth's edge, its tip 3.8 mm off the axis. Catches a find
    handed back at zero lateral force: the tip crept toward the axis at 0.4 mm/s and the jam check
    failed the INSERT 1.5 mm in ("jammed at depth 1.5 mm ... while pushing 6.5 N")."""
    result = run_case(Case(7.8, -50.2, "SPIRAL", 12.0, 3.0, 8.0, panda=True), 2, False)
    assert result.ok, result
    assert result.tilt_deg < WINDOW_DEG + OVERSHOOT_DEG, result


def test_a_part_tipped_into_the_mouth_is_a_find() -> None:
    """``SEARCH SPIRAL RADIUS 16 mm PITCH 5 mm`` from 12 mm off, seed 0: the peg tips 10 deg toward
    the hole 5.6 mm from its axis, its rim in the mouth but not 1 mm deeper. Catches a search that
    drags on a part so tipped: its low rim caught on the mouth's inner edge was pulled out sideways
    until it knocked free, 260 N at the wrist, a protective stop."""
    result = run_case(Case(12.0, 315.0, "SPIRAL", 16.0, 5.0, 8.0, 15.0), 0, False)
    assert result.ok, result
    assert result.peak_n < SENSOR_RATING_N, result
