"""Which face an INSERT's approach meets (cosmos.runtime.landing_zone.square_face), and its FORCE.

An INSERT's approach lands slowly on a steel face square to it (the flat around the hole), as a
CONTACT's does, and at its SPEED on the hole's 45 deg chamfer (cosmos.osc.push_speed). The faces
are the scene file's: the fixture's top is level, its chamfers are at 45 deg to the axis.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.lang import compile_program
from cosmos.plan import DepthReached, SegmentKind
from cosmos.robots import ROBOTS
from cosmos.runtime import landing_zone
from cosmos.runtime.foresight_cache import workcell
from cosmos.runtime.landing_zone import INSERT_TRACE_STEPS, square_face, surface_ahead, tool_points
from cosmos.workcell import fixture_frames

DOWN = np.array([0.0, 0.0, -1.0])


@pytest.mark.parametrize("robot", ["puma560", "panda"])
@pytest.mark.parametrize(
    ("offset_mm", "height_mm", "square"),
    [
        ((6.0, -5.0), 10.0, True),
        ((16.0, 0.0), 10.0, True),
        ((2.0, 0.0), 2.0, False),
        ((1.0, 0.0), 5.0, False),
    ],
)
def test_the_top_face_is_square_to_an_insert_down_and_the_chamfer_is_not(
    robot: str, offset_mm: tuple[float, float], height_mm: float, square: bool
) -> None:
    """Catches the flat top face taken for the chamfer (the INSERT then met it at its SPEED: 65-80 N
    from ``hole + (6 mm, -5 mm, 10 mm)``) and the chamfer taken for a flat face (its insertion would
    start from a crawl): the peg's end meets the top face 10 mm down, the chamfer within 7 mm."""
    cell = workcell(robot, "peg")
    hole = fixture_frames(ROBOTS[robot])["hole"]
    start = hole.position + 1e-3 * np.array([*offset_mm, height_mm])
    points = tool_points(start, cell.home_tool_rotation, cell.tool_sections)
    distance, solid = surface_ahead(cell.solids, points, DOWN, 0.3)
    assert cell.solids[solid].geom.startswith("hole_top" if square else "hole_chamfer")
    if square:
        assert distance == pytest.approx(height_mm * 1e-3, abs=2e-5)
        assert surface_ahead(cell.solids, points, DOWN, 0.3, INSERT_TRACE_STEPS) == (distance, solid)
    assert square_face(cell.solids, points, DOWN, distance) is square


def test_a_peg_over_its_hole_is_not_traced_down_the_bore(monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches an INSERT's approach traced to the end of the trace's 200 steps: ``peg_in_hole.cos``'s
    peg, centred 2 mm over its hole, stepped down the bore's 0.12 mm clearance for 60 ms at its
    INSERT's start (the bench's ``peg_in_hole.cos`` went 1.06 -> 1.28); it meets no square face within
    the INSERT's steps and keeps its SPEED onto the chamfer. Its only traced segment is the INSERT's."""
    from cosmos.bench.programs import PROGRAMS_DIR, executor_run

    steps = []
    stepped = landing_zone._step
    monkeypatch.setattr(landing_zone, "_step", lambda *args: steps.append(1) or stepped(*args))
    assert executor_run(PROGRAMS_DIR / "peg_in_hole.cos").ok
    assert 0 < len(steps) <= 20  # 8 steps at most, each the points least far along, then the rest (was 400)


def test_an_inserts_approach_carries_its_force() -> None:
    """Catches an INSERT's approach compiled without its FORCE: its landing's speed is chosen for
    the FORCE's bar (cosmos.osc.landing.landing_speed), as a CONTACT's is."""
    source = "MOVE TO hole + (6 mm, -5 mm, 10 mm)\nINSERT DOWN DEPTH 25 mm FORCE 4 N\n"
    plan = compile_program(source, "test.cos", fixture_frames(ROBOTS["puma560"]))
    approach = next(s for s in plan.segments if s.kind is SegmentKind.CONTACT_APPROACH)
    assert isinstance(approach.completion, DepthReached)
    assert approach.completion.force_n == pytest.approx(4.0)
