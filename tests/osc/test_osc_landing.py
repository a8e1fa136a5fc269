"""A CONTACT's landing profile (:mod:`cosmos.osc.landing`), its compiled form, the surface traced."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.landing import LANDING_MIN_MPS, landing_limit, landing_speed
from cosmos.robots import ROBOTS
from cosmos.runtime.foresight_cache import workcell
from cosmos.runtime.kernels.cruise import landing_limit as compiled_landing_limit
from cosmos.runtime.landing_zone import contact_ramps, surface_ahead, tool_end_points
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


def test_the_compiled_profile_matches_the_reference() -> None:
    """Catches the servo's compiled landing limit drifting from the readable reference."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        args = (
            float(rng.uniform(0.001, 0.05)),
            float(rng.uniform(-2e-3, 5e-3)),
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


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_the_hole_top_is_found_under_the_peg_and_is_stiff(robot: str) -> None:
    """Catches a trace that misses the hole fixture's top face (or stops short of it) under a peg
    16 mm off the hole's axis, 10 mm above it: the distance is the height over the face as the
    scene file places it (the hole site is on the top face), the face's contact is steel (under
    1 mm: the tool's 0.3 mm) and the table's is not (1.5 mm)."""
    cell = workcell(robot, "peg")
    hole = fixture_frames(ROBOTS[robot])["hole"]
    start = hole.position + np.array([0.016, 0.0, 0.010])
    points = tool_end_points(start, cell.home_tool_rotation, cell.tool_sections)
    distance, solid = surface_ahead(cell.solids, points, DOWN, 0.3)
    assert distance == pytest.approx(0.010, abs=2e-5)
    ramps = contact_ramps(robot)
    assert ramps[cell.solids[solid].geom] < 0.001
    assert ramps["table_top"] == pytest.approx(0.0015, rel=0.01)
