"""The Panda's INSERT from beyond the chamfers' reach goes in (issue 14: sweeps' jams).

``CONTACT DOWN`` lands the peg 3.7-6.2 mm off the hole's axis (the program aims 3.6 mm off,
the varied hole moves, the guarded approach drifts), beyond the chamfers' 2.62 mm of capture
(tests/run/test_run_insert.py): the peg's flat end rests on the fixture's top face. The
compliant rotations tip its far side into the mouth; then

* on the mouth's edge, tilted 10.8 deg, the edge pushed the peg toward the hole with
  ``F tan(theta)``, 2.3 N of the 12 N push, against friction 0.43-0.64 times it: the peg crept
  at 0.5 mm/s or not at all and the INSERT failed "jammed at depth 0.4-1.5 mm";
* dropped into the mouth still tilted 10.85 deg, the peg's chamfer met the hole's at
  45 - 10.85 = 34 deg, which friction 0.70 holds (tan 34 deg = 0.67): "jammed at 2.9 mm"
  (and, righted more slowly than the contact's moment tipped it, at 2.8 mm and 5.9 deg).

Each case is a run of the sweep that failed on main (``cosmos sweep P --runs 16 --workers 2
--vary friction='uniform(0.4,0.8)' --vary hole.x='normal(0,1mm)'``, its values and noise
seed), judged from the run's log: the INSERT ends ``done`` with its depth reached, the tool
point 25 mm below the mouth (the welded peg's tip within the bore's clearance of the moved
hole's axis; a held peg's tool point is the gripper's), and the peg
upright within Whitney's wedging bound ``c / mu`` (0.24 mm over 20 mm, steel 0.45: 1.5 deg)
once deep, as a peg in a 0.12 mm radial clearance must be (geometry, not the controller's
own figure: 0.24 mm over a 25 mm engagement is 0.55 deg).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from run_support import GRASPED_PEG_INSERT, HOLE_MOUTH_M

import cosmos

WELDED = """ROBOT panda
MOVE TO hole + (3 mm, -2 mm, 8 mm) SPEED 0.15 m/s
CONTACT DOWN FORCE 6 N SPEED 8 mm/s
INSERT DOWN DEPTH 25 mm FORCE 12 N TIMEOUT 30 s
"""
GRASPED = "ROBOT panda\n" + GRASPED_PEG_INSERT
INSERTED_M = 0.025
"""The INSERT's DEPTH below the mouth, less the 1 mm its CONTACT may rest above it [m]."""
CLEARANCE_AXIS_M = 0.5e-3
"""The tip within this of the hole's axis: 0.12 mm radial clearance, the polygon's corners [m]."""
UPRIGHT_RAD = np.radians(1.5)
"""Whitney's bound ``c / mu``: 0.24 mm / 20 mm over steel's 0.45 [rad]."""


@dataclass(frozen=True)
class Case:
    """A failed run of the sweep: its program, its drawn values and what main's INSERT did."""

    name: str
    program: str
    friction: float
    hole_x_m: float
    seed: int
    on_main: str


CASES = (
    Case("welded-run7", WELDED, 0.4351591453332909, -0.0028666202658479373, 23012616, "jammed at 0.4 mm"),
    Case("welded-run1", WELDED, 0.5767256922239811, -0.00014657623213710285, 673228719, "jammed at 1.5 mm"),
    Case("welded-run12", WELDED, 0.6421611831210303, -0.0010230401136248866, 2090914255, "jammed at 1.0 mm"),
    Case("grasped-run6", GRASPED, 0.700990216699344, -0.00035963273925785944, 2471122328, "jammed at 2.9 mm"),
    Case("grasped-run7", GRASPED, 0.4351591453332909, -0.0028666202658479373, 23012616, "jammed at 0.6 mm"),
)


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_a_peg_beyond_the_chamfers_goes_in(tmp_path: Path, case: Case) -> None:
    vary = {"friction": case.friction, "hole.x": case.hole_x_m}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(case.program, seed=case.seed, log=tmp_path / "run.mcap", vary=vary)
    line = len(case.program.strip().splitlines())
    closing = [e for e in run.events if e.line == line and e.kind in ("done", "failed")]
    assert closing, f"{case.name}: the INSERT never ended"
    assert closing[0].kind == "done" and "reached" in closing[0].reason, (
        f"{case.name}: {closing[0].kind} ({closing[0].reason}); main: {case.on_main}"
    )
    state = run.record.state
    inserting = state.line == line
    tip = state.x[inserting]
    mouth = HOLE_MOUTH_M + np.array([case.hole_x_m, 0.0, 0.0])
    assert mouth[2] - tip[:, 2].min() >= INSERTED_M - 1e-3
    if case.program is WELDED:  # the tool point is the peg's tip (held, it is the gripper's)
        assert np.linalg.norm(tip[-1, :2] - mouth[:2]) <= CLEARANCE_AXIS_M
    _, x, y, _ = state.quat[inserting][-1]  # w, x, y, z
    axis_z = 1.0 - 2.0 * (x * x + y * y)  # the tool's z axis (the peg, down) along world z
    tilt = np.arccos(np.clip(-axis_z, -1.0, 1.0))
    assert tilt <= UPRIGHT_RAD, f"{case.name}: the peg stands {np.degrees(tilt):.2f} deg off the bore's axis"
