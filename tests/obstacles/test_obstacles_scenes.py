"""Obstacle avoidance in the simulated workcell: five scenes, avoidance on and off, a local minimum.

Each scene drives the arm from home with goal motion (seed eq. 20-21) and the
obstacle field in the runtime. Judged by the simulator: the tool site's
distance to the goal, MuJoCo's contacts and ``mj_geomDistance`` clearances.
"""

from __future__ import annotations

import dataclasses

import pytest

from cosmos.obstacles import FieldParameters
from cosmos.obstacles.obstacle import box, cylinder, sphere
from tests.obstacles.obstacle_scenes import Scene, run

ALONG_Y = (0.596, 0.25, 0.457)  # from home (0.596, -0.150, 0.457): 400 mm sideways

SCENES = {
    # The straight line passes 14 mm from the ball's centre, through the peg's path.
    "sphere_on_the_line": Scene("sphere", (sphere("ball", (0.61, 0.05, 0.52), 0.05),), ALONG_Y, 3.0),
    # A post hanging from above; its foot is 10 mm into the elbow's sweep as joint 1 turns 60 deg.
    "post_by_the_elbow": Scene(
        "post", (cylinder("post", (0.264, 0.056, 1.29), 0.04, 0.5),), (0.45, 0.45, 0.457), 4.0
    ),
    # The arm reaches through a 220 mm slot in a wall; the straight line grazes the slot's side.
    "wall_with_a_gap": Scene(
        "slot",
        (
            box("wall_left", (0.70, -0.465, 0.625), (0.02, 0.27, 0.75)),
            box("wall_right", (0.70, 0.095, 0.625), (0.02, 0.41, 0.75)),
        ),
        (0.80, -0.21, 0.40),
        3.0,
    ),
    # A ball crossing the path at 150 mm/s when the tool gets there. Started at x = 0.45 (with goal
    # motions' speed ramped up from rest, the tool 25 ms later to the crossing) or at 0.454 (without
    # the ramp), it blocks the arm for over a second and the local-minimum detector takes that for
    # a minimum: it does not know that a moving obstacle's minimum moves on.
    "moving_sphere": Scene(
        "moving", (sphere("ball", (0.458, 0.10, 0.53), 0.05, velocity_mps=(0.15, 0.0, 0.0)),), ALONG_Y, 4.0
    ),
    # A rock under the forearm's sweep, 130 mm from the peg's path.
    "forearm_only": Scene("forearm", (sphere("rock", (0.42, 0.0, 0.73), 0.05),), ALONG_Y, 3.0),
}


@pytest.mark.parametrize("name", list(SCENES))
def test_the_arm_reaches_the_goal_without_touching(name: str, record_property) -> None:
    outcome = run(SCENES[name], avoid=True, stop_at_goal_m=0.002)
    record_property("goal_error_mm", round(1000 * outcome.goal_error_m, 2))
    record_property("min_clearance_mm", round(1000 * outcome.min_clearance_m, 1))
    assert outcome.contacts == []
    assert outcome.min_clearance_m > 0.005
    assert outcome.goal_error_m < 0.005


@pytest.mark.parametrize("name", list(SCENES))
def test_without_avoidance_the_same_move_collides(name: str) -> None:
    outcome = run(SCENES[name], avoid=False, stop_on_contact=name != "forearm_only")
    assert outcome.contacts, "the scene is not in the way"
    if name == "forearm_only":
        assert {arm for arm, _ in outcome.contacts} == {"link3"}  # the forearm, never the tool


def test_a_wall_across_the_path_is_a_local_minimum_named_before_any_timeout() -> None:
    wall = Scene("minimum", (box("wall", (0.65, 0.05, 0.7), (0.6, 0.02, 1.0)),), ALONG_Y, 4.0)
    outcome = run(wall, avoid=True, detect=True)
    assert outcome.contacts == []
    assert outcome.local_minimum is not None
    assert outcome.local_minimum.obstacle == "wall"
    assert outcome.duration_s < 3.0  # the free move takes ~2 s
    assert "near obstacle 'wall'" in outcome.local_minimum.message()


def test_the_detector_stays_quiet_when_the_arm_gets_through() -> None:
    for name in SCENES:
        assert run(SCENES[name], avoid=True, detect=True, stop_at_goal_m=0.002).local_minimum is None


def test_the_approach_damping_keeps_a_fast_arm_farther_away() -> None:
    fast = dataclasses.replace(SCENES["wall_with_a_gap"], max_speed=0.5)
    undamped = run(fast, parameters=dataclasses.replace(FieldParameters(), damping_ns_per_m=0.0))
    damped = run(fast)
    assert damped.contacts == [] and damped.goal_error_m < 0.005
    assert damped.min_clearance_m > undamped.min_clearance_m + 0.003
