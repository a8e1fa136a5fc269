"""A SLIDE in a turned task frame on a high-friction table arrives, on its line (issue 14, items 4-5).

The table's friction acts on the tool as a force; eq. 19's unit mass feels ``Lambda^-1`` of it,
and the arm's inverse inertia is not isotropic, so a friction along the slide pushed the tool
across it: in a task frame turned 30 deg, at friction 0.8 and 20 N, the tool ran 2.1-2.2 mm off
its line for the whole slide, the integral that took over at the reference's end hunted +-2 mm at
up to 42 mm/s, and the SLIDE failed ("did not arrive within 1 s"). The controller now measures the
surface's friction and compensates it toward the motion axes' intent
(:mod:`cosmos.osc.surface_friction`). Judged from the run's own log.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from run_support import BOTH_PLANTS

import cosmos
from cosmos.runlog import read_log

PROGRAM = """\
FRAME work = table + (0, 40 mm, 0) RPY (180 deg, 0, 30 deg)
SPEED 0.2 m/s
MOVE TO work + (0, 0, 30 mm)
CONTACT +Z IN work FORCE 20 N SPEED 15 mm/s TIMEOUT 5 s
SLIDE +X IN work BY 40 mm SPEED 30 mm/s
"""
YAW_RAD = math.radians(30.0)


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_a_slide_in_a_turned_frame_on_a_rough_table_arrives_on_its_line(tmp_path: Path, ideal: bool) -> None:
    """SLIDE +X IN a frame turned 30 deg, 40 mm at 30 mm/s, 20 N, the table's friction 0.8: the SLIDE
    arrives (1 mm, 1 deg, at rest), its tool stays within 1.5 mm of its line (1.21 mm realistic, 0.63
    mm ideal, all of it in the breakaway) and covers 40 mm within 1 mm. Catches the friction's push
    across the slide left to eq. 19 (2.17 and 2.19 mm off the line for the whole slide, then the
    integral's hunting at the goal: "did not arrive within 1 s", 1.5 and 1.9 mm from its goal)."""
    log = tmp_path / "slide_friction.mcap"
    run = cosmos.run(PROGRAM, seed=0, ideal=ideal, vary={"friction": 0.8}, log=log)
    assert run.ok, run.outcome
    record = read_log(log)
    slides = [s for s in record.segments if s.kind == "slide"]
    assert len(slides) == 1
    state = record.state
    x = state.x[state.segment == slides[0].segment]
    along = np.array((math.cos(YAW_RAD), math.sin(YAW_RAD), 0.0))
    across = np.array((-math.sin(YAW_RAD), math.cos(YAW_RAD), 0.0))
    travel = x - x[0]
    deviation = float(np.max(np.abs(travel @ across)))
    assert deviation <= 1.5e-3, f"the tool ran {deviation * 1e3:.2f} mm off its line"
    assert float(travel[-1] @ along) == pytest.approx(0.040, abs=1e-3)
