"""Contact held while sliding (issue 14, item 5): representative cases of tests/run/slide_grid.py.

The whole grid (54 cases) runs with ``python tests/run/slide_grid.py``; its figures
are in the README. Here: a heavy slow diagonal slide, which holds, and the worst
case the grid finds, light and fast, which does not yet (strict xfail with the
measured cause, so that a fix shows).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from slide_grid import Case, run_case


def test_heavy_slow_diagonal_slide_holds_its_push(tmp_path: Path) -> None:
    """30 N, 5 mm/s, world diagonal: the push never below 50 % of 30 N and within 15 % for 95 % of
    the slide, at 80 % of SPEED or more. Catches a slide that loses or spikes its contact, or
    crawls, where the contact is firm."""
    result = run_case(Case(30.0, 5.0, "diagonal", "world"), tmp_path)
    assert result.ok, result


@pytest.mark.xfail(
    strict=True,
    reason=(
        "physics: at 5 N and 50 mm/s the tool's soft contact (solref 0.2 s) creeps out of the "
        "table under the pyramidal friction cone and the contact drops (push down to 0-5 % of "
        "its setpoint); the elliptic cone with impratio 10 keeps the push above 58 % in most "
        "cases but needs a force loop retuned for it (CONTACT overshoot 51-57 %)"
    ),
)
def test_light_fast_slide_holds_its_push(tmp_path: Path) -> None:
    """5 N, 50 mm/s, +X: the worst case of the grid, judged on the same bar."""
    result = run_case(Case(5.0, 50.0, "+X", "world"), tmp_path)
    assert result.ok, result
