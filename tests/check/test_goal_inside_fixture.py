"""The checker warns of a goal inside a fixture, as MuJoCo's own geometry queries place it."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import cosmos
from cosmos.runtime.fixture_solids import signed_distances, top_above
from cosmos.runtime.foresight_cache import workcell
from tests.check import mujoco_probe

PROGRAMS = sorted((Path(__file__).resolve().parents[2] / "programs").glob("*.cos"))
INSIDE = re.compile(
    r"^(?P<keyword>MOVE TO|MOVE BY):(?: in (?P<context>[^,]+),)? "
    r"(?:the (?P<what>goal|VIA point \d) is|at the goal the tool's axis, (?P<back>\d+) mm back from the "
    r"tool point, is|at the goal the tool's tip, (?P<ahead>[\d.]+) mm past the tool point, is) "
    r"(?P<depth>[\d.]+) mm inside the (?P<kind>fixture|obstacle) '(?P<fixture>\w+)' "
    r"\(below its top at z = (?P<top>-?[\d.]+) mm\); the run will stop (?P<ending>at the touch|short of it)$"
)


SIDE = re.compile(
    r"^(?P<keyword>MOVE TO|MOVE BY):(?: in (?P<context>[^,]+),)? at the (?P<what>goal) the tool's side, "
    r"(?P<back>\d+) mm back from the tool point, is (?P<depth>[\d.]+) mm into the (?P<kind>fixture|obstacle) "
    r"'(?P<fixture>\w+)'; the run will stop (?P<ending>at the touch|short of it)$"
)


def inside_warnings(source: str) -> list[tuple[int, re.Match[str]]]:
    """The goal-inside-a-fixture warnings of ``source``: (line, the message matched)."""
    found = []
    for warning in cosmos.check(source).warnings:
        if " mm inside the " in warning.message or " mm into the " in warning.message:
            match = INSIDE.match(warning.message) or SIDE.match(warning.message)
            assert match is not None, warning.message
            found.append((warning.span.line, match))
    return found


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_solids_are_mujocos_geoms(robot: str) -> None:
    """Every fixture solid's signed distance equals MuJoCo's ``mj_geomDistance`` from a point-sized
    sphere, at 900 points around the table, the hole and the plate. Catches a solid read with the
    wrong pose or size (a box's full size for its half size, its rotation transposed), a geom of the
    scene missing from the cache, and an inside distance taken to the wrong face."""
    solids = workcell(robot).solids
    rng = np.random.default_rng(7)
    points = np.vstack(
        (
            rng.uniform((0.25, -0.7, -0.05), (1.0, 0.5, 0.32), size=(400, 3)),
            rng.normal((0.6, 0.15, 0.24), 0.03, size=(300, 3)),  # the hole
            rng.normal((0.45, -0.4, 0.24), (0.06, 0.05, 0.03), size=(200, 3)),  # the plate
        )
    )
    ours = signed_distances(solids, points).min(axis=1)
    compared = 0
    for point, distance in zip(points, ours, strict=True):
        theirs, _ = mujoco_probe.signed_distance(point, robot)
        if theirs < mujoco_probe.FAR_M:
            assert distance == pytest.approx(theirs, abs=1e-9), point
            compared += 1
        else:
            assert distance >= mujoco_probe.FAR_M - 1e-9, point
    assert compared > 400
    assert len({mujoco_probe.probe(robot).model.geom(s.geom).id for s in solids}) == len(
        mujoco_probe.probe(robot).fixture_geoms
    )


def _table(offset: tuple[float, float, float], robot: str = "puma560") -> np.ndarray:
    return mujoco_probe.site("table", robot)[0] + np.array(offset)


def _hole(offset: tuple[float, float, float]) -> np.ndarray:
    return mujoco_probe.site("hole")[0] + np.array(offset)


def _slope_after(above_m: float, into_m: float) -> np.ndarray:
    position, rotation = mujoco_probe.site("slope")
    return position + np.array((0.0, 0.0, above_m)) + into_m * rotation[:, 2]


# (program, line of the MOVE, its goal as MuJoCo places the fixture frames, arm)
CASES = [
    ("MOVE TO table + (0, 0, -30 mm)\n", 1, _table((0, 0, -0.03)), "puma560"),
    ("MOVE TO table + (100 mm, 50 mm, -2 mm)\n", 1, _table((0.1, 0.05, -0.002)), "puma560"),
    ("MOVE TO hole + (25 mm, 0, -20 mm)\n", 1, _hole((0.025, 0, -0.02)), "puma560"),
    ("MOVE TO hole + (0, 12 mm, -5 mm)\n", 1, _hole((0, 0.012, -0.005)), "puma560"),
    ("MOVE TO slope + (0, 0, -10 mm)\n", 1, _slope_after(-0.01, 0.0), "puma560"),
    ("MOVE TO table + (0, 0, 50 mm)\nMOVE BY (0, 0, -70 mm)\n", 2, _table((0, 0, -0.02)), "puma560"),
    (
        "MOVE TO slope + (0, 0, 30 mm)\nMOVE BY (0, 0, 60 mm) IN slope\n",
        2,
        _slope_after(0.03, 0.06),
        "puma560",
    ),
    ("ROBOT panda\nMOVE TO table + (0, 0, -30 mm)\n", 2, _table((0, 0, -0.03), "panda"), "panda"),
    (
        "ROBOT panda\nMOVE TO table + (0, 0, 40 mm)\nMOVE BY (0, 0, -45 mm)\n",
        3,
        _table((0, 0, -0.005), "panda"),
        "panda",
    ),
]


@pytest.mark.parametrize(("source", "line", "goal", "robot"), CASES)
def test_a_goal_inside_a_fixture_is_warned_with_mujocos_depth(
    source: str, line: int, goal: np.ndarray, robot: str
) -> None:
    """Goals inside the table, the hole's block and the tilted plate, written in world and task
    frames, by MOVE TO and by MOVE BY from a known pose, on both arms: one warning at the MOVE,
    naming the fixture MuJoCo finds the goal in, with the top MuJoCo's ray meets above it and the
    depth below that top. Catches such a goal passing check (the run stops at the touch), a wrong
    fixture or depth, a MOVE BY added to the wrong start, a task frame's axes ignored."""
    distance, fixture = mujoco_probe.signed_distance(goal, robot)
    assert distance < -1e-4  # the case is what it claims
    top, hit = mujoco_probe.top_at(float(goal[0]), float(goal[1]), robot)
    assert hit == fixture
    found = inside_warnings(source)
    assert [at for at, _ in found] == [line], found
    match = found[0][1]
    assert (match["what"], match["kind"], match["ending"]) == ("goal", "fixture", "at the touch")
    assert match["fixture"] == fixture
    assert float(match["top"]) == pytest.approx(top * 1e3, abs=0.051)
    assert float(match["depth"]) == pytest.approx((top - goal[2]) * 1e3, abs=0.051)


def test_a_via_point_deeper_than_it_is_passed_is_warned() -> None:
    """A VIA point 30 mm into the table (it counts as passed within 10 mm) is warned; one 5 mm in is
    not (the tool turns to the goal before it touches). Catches VIA points left unchecked, and judged
    like goals (a warning for a via the tool never reaches)."""
    deep = "MOVE TO (0.6, -0.15, 0.3) VIA (0.6, -0.15, 0.17)\n"
    found = inside_warnings(deep)
    assert [(at, m["what"], m["fixture"]) for at, m in found] == [(1, "VIA point 1", "table")]
    top, _ = mujoco_probe.top_at(0.6, -0.15)
    assert float(found[0][1]["depth"]) == pytest.approx((top - 0.17) * 1e3, abs=0.051)
    assert not inside_warnings("MOVE TO (0.6, -0.15, 0.3) VIA (0.6, -0.15, 0.195)\n")


def test_the_tools_axis_inside_a_fixture_is_warned() -> None:
    """With the tool pointing up 50 mm above the table, the tool point is free but its axis runs
    down through the table top to the flange: warned, at the axis's deepest point, which MuJoCo
    finds inside the table at the depth said. Catches the tool's extent ignored, or taken the wrong
    way along its axis (a tool pointing down over the table would be warned)."""
    found = inside_warnings("MOVE TO table + (0, 0, 50 mm) RPY (0, 0, 0)\n")
    assert len(found) == 1
    match = found[0][1]
    back_m, depth_m = int(match["back"]) / 1e3, float(match["depth"]) / 1e3
    point = _table((0, 0, 0.05 - back_m))  # the tool's z is the world's
    distance, fixture = mujoco_probe.signed_distance(point)
    assert distance < 0.0 and fixture == match["fixture"] == "table"
    top, _ = mujoco_probe.top_at(float(point[0]), float(point[1]))
    assert depth_m == pytest.approx(top - point[2], abs=5.1e-5)
    assert not inside_warnings("MOVE TO table + (0, 0, 50 mm)\n")  # pointing down: the axis is above


NO_WARNING = [
    "MOVE TO hole + (0, 0, -30 mm)\n",  # in the bore: no solid
    "MOVE TO table\n",  # on the surface: the run arrives
    "MOVE TO table + (0, 0, 20 mm)\nCONTACT DOWN FORCE 5 N\nMOVE BY (0, 0, -50 mm)\n",  # start unknown
    "MOVE TO table + (0, 0, -30 mm) UNTIL FORCE > 5 N\n",  # a guarded move: meant to touch
    "MOVE TO table + (0, 0, 20 mm)\nCONTACT DOWN FORCE 5 N\nSLIDE +X BY 40 mm SPEED 10 mm/s\n",
    "MOVE TO hole + (0, 0, 2 mm)\nINSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s\n",
    "MOVE TO (0.6, -0.15, 0.3)\nIF FORCE > 3 N\n  MOVE BY (0, 0, 50 mm)\nEND\nMOVE BY (0, 0, -150 mm)\n",
]


@pytest.mark.parametrize("source", NO_WARNING)
def test_goals_meant_to_touch_or_outside_are_not_warned(source: str) -> None:
    """No warning where MuJoCo finds the goal outside every fixture (the hole's bore, the table's
    surface), for statements meant to touch (CONTACT, SLIDE, INSERT, MOVE ... UNTIL FORCE), and for
    a MOVE BY whose start the text does not fix (after a CONTACT, after an IF that may move). Catches
    the bore taken for solid, contact statements warned, and a MOVE BY from a guessed start."""
    assert not inside_warnings(source)
    assert mujoco_probe.signed_distance(_hole((0, 0, -0.03)))[0] > 0.0
    assert mujoco_probe.signed_distance(_table((0, 0, 0)))[0] >= -1e-12


def test_the_top_is_found_across_seams_and_on_the_slope() -> None:
    """``top_above`` agrees with MuJoCo's ray down at random points inside each fixture (across the
    seam where a table leg meets the top, and under the tilted plate's face). Catches a top found at
    the first seam, or by the distance to the nearest face rather than straight up."""
    cell = workcell("puma560")
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(300):
        point = rng.uniform((0.28, -0.62, 0.0), (0.96, 0.42, 0.31))
        distance, fixture = mujoco_probe.signed_distance(point)
        if distance >= 0.0 or fixture == "floor":
            continue
        top, hit = mujoco_probe.top_at(float(point[0]), float(point[1]))
        solids = tuple(s for s in cell.solids if s.fixture == fixture)
        if hit != fixture:
            continue  # another fixture above this one's top (the plate over the table)
        assert top_above(solids, point) == pytest.approx(top, abs=1e-6), point
        checked += 1
    leg = np.array([0.33, -0.57, 0.05])  # inside a leg, under the table's top
    assert top_above(tuple(s for s in cell.solids if s.fixture == "table"), leg) == pytest.approx(0.2)
    assert checked > 20


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.name)
def test_shipped_programs_get_no_new_warning(program: Path) -> None:
    """The shipped programs check as before: the foresight adds no warning to the compiler's.
    Catches false alarms on real programs (the INSERT's depth, a CONTACT's search distance, a
    grasped object's goal, the Panda's moves)."""
    from cosmos.commands.fixture_cache import fixture_frames
    from cosmos.lang import compile_program

    source = program.read_text()
    compiled = compile_program(source, str(program), fixture_frames())
    assert [w.message for w in cosmos.check(program).warnings] == [w.message for w in compiled.warnings]


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_a_move_by_from_home_starts_where_the_programs_tool_is(robot: str) -> None:
    """``TOOL GRIPPER`` then ``MOVE BY`` from home: the goal is the gripper's tool point at the
    home keyframe (as MuJoCo places it with the gripper mounted) plus the offset, and the warning's
    depth is that goal's below the table's top. Catches the peg's home used for every tool (the
    Panda's gripper point is 45 mm lower than its peg's: a goal 20 mm inside passed as 25 mm above)."""
    import mujoco

    from cosmos.hand.tool import Tool
    from cosmos.robots import ROBOTS
    from cosmos.workcell import scene_spec

    model = scene_spec(ROBOTS[robot].scene_xml, Tool.GRIPPER, robot).compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_kinematics(model, data)
    home = data.site("tool").xpos.copy()
    top, _ = mujoco_probe.top_at(float(home[0]), float(home[1]), robot)
    drop_mm = round((home[2] - top + 0.02) * 1e3)
    found = inside_warnings(f"ROBOT {robot}\nTOOL GRIPPER\nMOVE BY (0, 0, -{drop_mm} mm)\n")
    assert [(at, m["fixture"]) for at, m in found] == [(3, "table")]
    # The deepest point is the fingertips', the lowest corner of the gripper's geoms at home.
    tip = min(_lowest_corner(model, data, g) for g in range(model.ngeom) if _on_the_tool(model, g))
    assert float(found[0][1]["depth"]) == pytest.approx((top - (tip - drop_mm / 1e3)) * 1e3, abs=0.051)
    assert float(found[0][1]["ahead"]) == pytest.approx((home[2] - tip) * 1e3, abs=0.051)


def _on_the_tool(model: Any, geom: int) -> bool:
    """Whether ``geom`` collides and belongs to the tool body or a body on it (the fingers)."""
    body, tool = int(model.geom_bodyid[geom]), model.body("tool").id
    while body not in (0, tool):
        body = int(model.body_parentid[body])
    return body == tool and bool(model.geom_contype[geom] != 0 or model.geom_conaffinity[geom] != 0)


def _lowest_corner(model: Any, data: Any, geom: int) -> float:
    """The lowest z of ``geom``'s bounding box (MuJoCo's ``geom_aabb``) as placed in ``data`` [m]."""
    centre, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
    signs = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    corners = data.geom_xpos[geom] + (centre + signs * half) @ data.geom_xmat[geom].reshape(3, 3).T
    return float(corners[:, 2].min())


def test_points_inside_are_found_past_the_bounding_boxes() -> None:
    """At 600 random points of the workcell, ``point_inside`` finds a fixture exactly where MuJoCo
    finds the point deeper than 0.1 mm inside one, and that fixture. Catches the first look by
    bounding boxes skipping a solid that holds the point (the tilted plate's box taken unrotated, a
    cylinder's length for its half length)."""
    from cosmos.runtime.fixture_solids import bounds
    from cosmos.runtime.goals_in_fixtures import DEEPER_THAN_M, Solids, point_inside

    solids = workcell("puma560").solids
    packed = Solids(solids, *bounds(solids))
    rng = np.random.default_rng(11)
    inside = 0
    for point in rng.uniform((0.25, -0.7, -0.05), (1.0, 0.5, 0.32), size=(600, 3)):
        distance, fixture = mujoco_probe.signed_distance(point)
        found = point_inside(packed, point, None, 0.0, DEEPER_THAN_M)
        if distance < -DEEPER_THAN_M - 1e-9:
            assert found is not None and found.fixture == fixture, point
            inside += 1
        elif distance > -DEEPER_THAN_M + 1e-9:
            assert found is None, point
    assert inside > 50


def test_a_loop_is_warned_once_at_the_pass_that_goes_in() -> None:
    """``REPEAT 5`` of ``MOVE BY (0, 0, -30 mm)`` from 100 mm above the table: the fourth pass's
    goal is 20 mm inside (as MuJoCo's ray finds the top), and the run stops there, so one warning,
    naming the pass. Catches a warning per pass after the first stop (the later goals are never
    reached), and a warning that does not say which pass."""
    found = inside_warnings("MOVE TO table + (0, 0, 100 mm)\nREPEAT 5\n  MOVE BY (0, 0, -30 mm)\nEND\n")
    assert [(at, m["context"]) for at, m in found] == [(3, "REPEAT pass 4 of 5 at line 2")]
    top, _ = mujoco_probe.top_at(*mujoco_probe.site("table")[0][:2])
    goal_z = mujoco_probe.site("table")[0][2] + 0.1 - 4 * 0.03
    assert float(found[0][1]["depth"]) == pytest.approx((top - goal_z) * 1e3, abs=0.051)
