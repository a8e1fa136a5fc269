"""An INSERT that goes its DEPTH through air inserted nothing (issue 14: outcomes that are true).

DEPTH counts from where the INSERT starts. Started higher above the hole than its DEPTH, an
INSERT without a held contact used to approach its whole DEPTH in air and report "depth 20.0 mm
reached" with the peg still 20 mm above the mouth. A part entering its hole meets the chamfer
or the bore: MuJoCo's contacts of the tool with the fixtures tell the two apart, not the wrist
force alone (an aligned peg slides into the bore at under 1 N).
"""

from __future__ import annotations

from pathlib import Path

import cosmos
from run_support import HOLE_MOUTH_M

DEPTH_MM = 20.0


def _insert(tmp_path: Path, height_mm: float, name: str) -> cosmos.Run:
    program = f"MOVE TO hole + (0, 0, {height_mm} mm)\nINSERT DOWN DEPTH {DEPTH_MM} mm FORCE 12 N\n"
    return cosmos.run(program, log=tmp_path / f"{name}.mcap", seed=0)


def test_an_insert_through_air_fails(tmp_path: Path) -> None:
    """From 40 mm above the mouth, DEPTH 20 mm ends 20 mm above it (measured in the log): the
    INSERT fails at its line, saying it touched nothing. Catches the false "depth 20.0 mm reached"."""
    run = _insert(tmp_path, 40.0, "air")
    assert not run.ok and run.outcome is not None
    assert run.outcome.span is not None and run.outcome.span.line == 2
    assert "went its DEPTH of 20.0 mm touching nothing" in run.outcome.reason, run.outcome.reason
    above_mm = (run.record.state.x[-1][2] - HOLE_MOUTH_M[2]) * 1e3
    assert above_mm > 15.0, f"the tip is {above_mm:.1f} mm above the mouth: it did reach the hole"


def test_an_aligned_peg_that_slides_in_untouched_by_force_is_inserted(tmp_path: Path) -> None:
    """From 2 mm above on the hole's axis, seed 0, the realistic plant: the wrist never feels 2 N
    (the approach's touch), yet the peg is 18 mm into the bore. It succeeds, the tip measured
    18 mm below the mouth. Catches a touch judged on the wrist force alone."""
    run = _insert(tmp_path, 2.0, "aligned")
    assert run.ok, run.outcome
    inserting = run.record.state.line == 2
    peak_n = max(abs(f) for f in run.record.state.wrench[inserting, :3].ravel())
    assert peak_n < 2.0, f"the wrist felt {peak_n:.1f} N: this run no longer tests the untouched case"
    below_mm = (HOLE_MOUTH_M[2] - run.record.state.x[-1][2]) * 1e3
    assert abs(below_mm - (DEPTH_MM - 2.0)) < 1.0, f"the tip is {below_mm:.1f} mm below the mouth"
