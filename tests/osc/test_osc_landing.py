"""A CONTACT's landing profile (:mod:`cosmos.osc.landing`), its compiled form, the surface traced."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.landing import (
    IMPACT_MAX_N,
    IMPACT_STIFFNESS_N_PER_M,
    LANDING_MIN_MPS,
    LANDING_OVER_M,
    bar_n,
    landing_limit,
    landing_speed,
)
from cosmos.osc.orientation import so3_exp
from cosmos.robots import ROBOTS
from cosmos.runtime.fixture_solids import FixtureSolid, signed_distances
from cosmos.runtime.foresight_cache import workcell
from cosmos.runtime.kernels.cruise import landing_limit as compiled_landing_limit
from cosmos.runtime.landing_zone import TRACE_TOLERANCE_M, contact_ramps, surface_ahead, tool_points
from cosmos.workcell import fixture_frames

DOWN = np.array([0.0, 0.0, -1.0])


def test_the_profile_is_a_constant_deceleration_to_the_landing_speed() -> None:
    """Catches a profile that is not ``v^2 = v_l^2 + 2 a s`` (a body braking at ``a`` from ``V_max``
    reaches ``v_l`` where ``s`` = 0), or one that brakes a tool already under it (``V_max`` below)."""
    v_max, v_l, a = 0.02, 0.003, 0.1
    for s in (1e-4, 5e-4, 1e-3, 1.5e-3):
        limit, brake = landing_limit(v_max, s, v_l, a)
        assert limit == pytest.approx(min(v_max, math.sqrt(v_l**2 + 2 * a * s)))
        assert brake == (a if limit < v_max else 0.0)
    assert landing_limit(v_max, -1e-3, v_l, a) == (v_l, 0.0)  # past the point: v_l, no feedforward
    assert landing_limit(v_max, 1.0, v_l, a) == (v_max, 0.0)  # far off
    assert landing_limit(v_max, 0.0, 0.0, a) == (v_max, 0.0)  # no landing


def test_a_landing_is_over_past_its_surface_untouched() -> None:
    """Catches the landing held on past a surface that is not there (issue 14: over the hole fixture
    moved 30 mm down, CONTACT DOWN crawled at the landing's 3.8 mm/s from the nominal face on and
    found no contact in 6 s): ``LANDING_OVER_M`` (2 mm) past where ``v_l`` is held, the limit is
    ``V_max`` again, in the reference and the servo's compiled form; short of it, still ``v_l``."""
    v_max, v_l, a = 0.02, 0.0038, 0.1
    for limit in (landing_limit, compiled_landing_limit):
        assert limit(v_max, -LANDING_OVER_M + 1e-5, v_l, a) == (v_l, 0.0)
        assert limit(v_max, -LANDING_OVER_M - 1e-5, v_l, a) == (v_max, 0.0)
        assert limit(v_max, -0.030, v_l, a) == (v_max, 0.0)


def test_the_compiled_profile_matches_the_reference() -> None:
    """Catches the servo's compiled landing limit drifting from the readable reference."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        args = (
            float(rng.uniform(0.001, 0.05)),
            float(rng.uniform(-4e-3, 5e-3)),
            float(rng.choice([0.0, rng.uniform(0.002, 0.01)])),
            float(rng.uniform(0.05, 1.0)),
        )
        assert compiled_landing_limit(*args) == pytest.approx(landing_limit(*args), abs=1e-15)


def test_the_landing_speed_falls_with_the_effective_mass() -> None:
    """Catches a landing speed that does not keep ``v_l sqrt(Lambda_n)`` fixed (a mass meeting a
    spring at ``v`` peaks at ``v sqrt(k m)``), or that passes the SPEED or falls under the speed
    the joints stick at."""
    assert landing_speed(20.0, 0.05) * math.sqrt(20.0) == pytest.approx(
        landing_speed(10.0, 0.05) * math.sqrt(10.0)
    )
    assert landing_speed(0.1, 0.02) == 0.02
    assert landing_speed(1e4, 0.02) == LANDING_MIN_MPS


def _spring_peak_n(mass_kg: float, stiffness_n_per_m: float, speed_mps: float) -> float:
    """The peak force of a mass meeting a linear spring at a speed, integrated (not the closed form)."""
    x, v, dt, peak = 0.0, speed_mps, 1e-7, 0.0
    while v > 0.0:
        v -= stiffness_n_per_m * x / mass_kg * dt
        x += v * dt
        peak = max(peak, stiffness_n_per_m * x)
    return peak


@pytest.mark.parametrize("force_n", [2.0, 3.0, 5.0, 8.0, 30.0])
@pytest.mark.parametrize("mass_kg", [8.8, 18.5])
def test_the_landing_speed_keeps_the_impact_under_the_bar(force_n: float, mass_kg: float) -> None:
    """A mass ``Lambda_n`` (the Panda's, the PUMA's over the hole) landing at ``landing_speed`` on the
    spring ``k_i`` peaks at 0.75 of the bar ``max(1.5 F, F + 5 N)`` or at IMPACT_MAX_N, whichever is
    less (the spring's peak integrated here, not taken from the code's closed form).

    Catches a landing speed chosen without the FORCE: 3.8 mm/s for every FORCE on the PUMA, where
    FORCE 3 N at SPEED 5 mm/s peaked at 8.2-9.7 N against its bar of 8 N."""
    speed = landing_speed(mass_kg, 0.05, force_n)
    peak = _spring_peak_n(mass_kg, IMPACT_STIFFNESS_N_PER_M, speed)
    assert peak == pytest.approx(min(0.75 * bar_n(force_n), IMPACT_MAX_N), rel=1e-3)
    assert landing_speed(mass_kg, 0.05, 0.0) == landing_speed(mass_kg, 0.05, 100.0)  # unknown: the most
    assert landing_speed(mass_kg, 0.05, 3.0) < landing_speed(mass_kg, 0.05, 8.0)


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_the_hole_top_is_found_under_the_peg_and_is_stiff(robot: str) -> None:
    """Catches a trace that misses the hole fixture's top face (or stops short of it) under a peg
    16 mm off the hole's axis, 10 mm above it: the distance is the height over the face as the
    scene file places it (the hole site is on the top face), the face's contact is steel (under
    1 mm: the tool's 0.3 mm) and the table's is not (1.5 mm)."""
    cell = workcell(robot, "peg")
    hole = fixture_frames(ROBOTS[robot])["hole"]
    start = hole.position + np.array([0.016, 0.0, 0.010])
    points = tool_points(start, cell.home_tool_rotation, cell.tool_sections)
    distance, solid = surface_ahead(cell.solids, points, DOWN, 0.3)
    assert distance == pytest.approx(0.010, abs=2e-5)
    ramps = contact_ramps(robot)
    assert ramps[cell.solids[solid].geom] < 0.001
    assert ramps["table_top"] == pytest.approx(0.0015, rel=0.01)


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_a_wall_is_found_where_the_tools_side_meets_it(robot: str) -> None:
    """``CONTACT -X`` from ``hole + (70 mm, 0, -30 mm)`` meets the fixture's outer wall (its facet at
    x = 45 mm off the hole's axis) with the peg's shank (radius 9.9125 mm), 15.09 mm ahead: the
    distance from the scene's geometry, written out here.

    Catches a trace from the rim of the tool's end alone (the peg's chamfered tip, 8.4 mm): it found
    the wall 16.7 mm ahead, and the approach met it at its SPEED before slowing."""
    cell = workcell(robot, "peg")
    hole = fixture_frames(ROBOTS[robot])["hole"]
    start = hole.position + np.array([0.070, 0.0, -0.030])
    points = tool_points(start, cell.home_tool_rotation, cell.tool_sections)
    distance, solid = surface_ahead(cell.solids, points, np.array([-1.0, 0.0, 0.0]), 0.3)
    assert distance == pytest.approx(0.070 - 0.045 - 0.0099125, abs=2e-5)
    assert cell.solids[solid].geom.startswith("hole_wall")


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_the_trace_among_the_solids_its_sweep_reaches_meets_what_the_trace_among_all_meets(
    robot: str,
) -> None:
    """Catches the cull before the trace (only the solids whose boxes the tool's sweep reaches:
    a CONTACT's start went from 9-11 ms to under 1 ms) leaving out a solid the tool meets: 90
    traces from random starts and directions, and straight down, against the trace among all."""
    from cosmos.runtime.landing_zone import _trace

    cell = workcell(robot, "peg")
    rng = np.random.default_rng(3)
    met = 0
    for k in range(90):
        start = rng.uniform((0.35, -0.4, 0.2), (0.8, 0.3, 0.5))
        direction = np.array([0.0, 0.0, -1.0]) if k % 3 == 0 else rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        points = tool_points(start, np.diag([1.0, -1.0, -1.0]), cell.tool_sections)
        culled, whole = (
            surface_ahead(cell.solids, points, direction, 0.3),
            _trace(cell.solids, points, direction, 0.3),
        )
        assert culled[1] == whole[1] and (culled[0] == whole[0] or abs(culled[0] - whole[0]) < 1e-4)
        met += whole[1] >= 0
    assert met >= 20  # the traces do meet solids


def _each_point_alone(
    solids: tuple[FixtureSolid, ...], points: np.ndarray, direction: np.ndarray, travel_m: float
) -> tuple[float, int]:
    """The sphere trace's definition, point by point: each point steps by its distance to the solids
    until it meets one (within the tolerance) or passes ``travel_m``, 200 steps at most; the least
    ``(distance, step, order)`` of those that met one gives the answer."""
    found = []
    for order, point in enumerate(points):
        at = 0.0
        for step in range(200):
            if at > travel_m:
                break
            distances = signed_distances(solids, point + at * direction)[0]
            if distances.min() < TRACE_TOLERANCE_M:
                found.append((at, step, order, int(distances.argmin())))
                break
            at += max(float(distances.min()), TRACE_TOLERANCE_M)
    at, _, _, solid = min(found, default=(math.inf, 0, 0, -1))
    return at, solid


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_the_trace_is_each_point_traced_alone(robot: str) -> None:
    """Catches the trace's shortcuts (the points least far along step first, and the others stop
    unstepped once one of them meets a solid; the first met found by argmin, not a scan) changing
    what it meets or where, to the last bit: 16 traces, straight down onto the table and the hole
    (where the lowest ring meets first at the second step) and in random directions, against each
    point traced alone."""
    from cosmos.runtime.landing_zone import _trace

    cell = workcell(robot, "peg")
    hole = fixture_frames(ROBOTS[robot])["hole"].position
    rng = np.random.default_rng(5)
    met = 0
    for k in range(16):
        start = rng.uniform((0.35, -0.4, 0.2), (0.8, 0.3, 0.5)) if k % 4 else hole + (0.01 * k, 0.0, 0.02)
        direction = DOWN if k % 2 == 0 else rng.normal(size=3)
        direction = direction / np.linalg.norm(direction)
        turn = (
            np.diag([1.0, -1.0, -1.0]) if k % 3 else so3_exp(rng.normal(size=3) * 0.2) @ np.diag([1, -1, -1])
        )
        points = tool_points(start, turn, cell.tool_sections)
        traced = _trace(cell.solids, points, direction, 0.3)
        assert traced == _each_point_alone(cell.solids, points, direction, 0.3)
        met += traced[1] >= 0
    assert met >= 8
