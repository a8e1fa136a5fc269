"""An INSERT that goes its DEPTH through air inserted nothing (issue 14: outcomes that are true).

DEPTH counts from where the INSERT starts. Started higher above the hole than its DEPTH, an
INSERT without a held contact used to approach its whole DEPTH in air and report "depth 20.0 mm
reached" with the peg still 20 mm above the mouth. A part entering its hole meets the chamfer
or the bore, or slides into the bore's clearance untouched: the plant tells these from air, by
MuJoCo's contacts and distances of the tool to the fixtures, where the wrist force alone cannot
(an aligned peg slides in at under 1 N, on the ideal plant touching nothing at all).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from run_support import BOTH_PLANTS, HOLE_MOUTH_M, PROGRAMS

import cosmos

DEPTH_MM = 20.0


def _insert(tmp_path: Path, height_mm: float, ideal: bool) -> cosmos.Run:
    program = f"MOVE TO hole + (0, 0, {height_mm} mm)\nINSERT DOWN DEPTH {DEPTH_MM} mm FORCE 12 N\n"
    return cosmos.run(program, log=tmp_path / "insert.mcap", seed=0, ideal=ideal)


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_an_insert_through_air_fails(tmp_path: Path, ideal: bool) -> None:
    """From 40 mm above the mouth, DEPTH 20 mm ends 20 mm above it (measured in the log): the
    INSERT fails at its line, saying it touched nothing. Catches the false "depth 20.0 mm reached"."""
    run = _insert(tmp_path, 40.0, ideal)
    assert not run.ok and run.outcome is not None
    assert run.outcome.span is not None and run.outcome.span.line == 2
    assert "went its DEPTH of 20.0 mm touching nothing" in run.outcome.reason, run.outcome.reason
    above_mm = (run.record.state.x[-1][2] - HOLE_MOUTH_M[2]) * 1e3
    assert above_mm > 15.0, f"the tip is {above_mm:.1f} mm above the mouth: it did reach the hole"


def test_an_aligned_peg_that_slides_in_untouched_is_inserted() -> None:
    """programs/peg_in_hole.cos (seed 0, the realistic plant) lowers the peg from 2 mm above the
    mouth on the hole's axis: the wrist never feels the approach's 2 N and MuJoCo reports no
    contact of the peg with the hole, yet the peg is 25 mm into the bore. It succeeds, the tip
    measured 25 mm below the mouth. Catches a touch judged on the wrist force alone, and one
    judged on MuJoCo's contacts alone ("went its DEPTH of 27.0 mm touching nothing")."""
    run = cosmos.run(PROGRAMS / "peg_in_hole.cos", seed=0)
    line = 9  # the INSERT
    inserting = run.record.state.line == line
    peak_n = max(abs(f) for f in run.record.state.wrench[inserting, :3].ravel())
    assert peak_n < 2.0, f"the wrist felt {peak_n:.1f} N: this run no longer tests the untouched case"
    (done,) = [e for e in run.events if e.line == line and e.kind == "done"]
    assert done.reason == "depth 27.0 mm reached", done.reason
    below_mm = (HOLE_MOUTH_M[2] - run.record.state.x[inserting][-1][2]) * 1e3
    assert abs(below_mm - 25.0) < 1.0, f"the tip is {below_mm:.1f} mm below the mouth"
