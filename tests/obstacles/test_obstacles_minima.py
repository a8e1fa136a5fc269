"""The local-minimum monitor on made-up distance histories, and obstacles from compiled statements."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.errors import CosmosError, Span, TaskFailure
from cosmos.obstacles import Influence, LocalMinimumDetector, from_step
from cosmos.plan import AddObstacle, ObstacleShape

WALL = (Influence("wall", "link5", 0.02, 80.0),)
FAINT = (Influence("wall", "link5", 0.02, 80.0), Influence("ball", "link3", 0.09, 0.5))
SPAN = Span("prog.cosmos", 3, 1, 3, 40)


def _feed(detector: LocalMinimumDetector, distances: list[float], influences, dt: float = 0.004):
    found = None
    for i, d in enumerate(distances):
        found = detector.update(i * dt, d, influences)
        if found is not None:
            return found, i * dt
    return found, None


def test_a_stalled_arm_held_by_an_obstacle_is_reported_after_the_window() -> None:
    # 0.5 s of progress at 0.25 m/s, then stuck 42 mm from the goal (with 1 mm of jitter).
    moving = list(np.linspace(0.17, 0.042, 125))
    stuck = [0.042 + 0.001 * np.sin(i) for i in range(500)]
    found, at = _feed(LocalMinimumDetector(), moving + stuck, FAINT)
    assert found is not None and found.obstacle == "wall" and found.link == "link5"
    assert at == pytest.approx(0.5 + 1.0, abs=0.05)  # one window after the stall began
    assert found.message() == (
        "MOVE TO stuck in a local minimum of the potential field near obstacle 'wall' (42 mm from the goal)"
    )
    error = found.error("MOVE TO", SPAN)
    assert isinstance(error, TaskFailure) and error.span == SPAN


def test_no_report_while_progressing_near_the_goal_or_without_an_obstacle() -> None:
    slow = list(np.linspace(0.3, 0.2, 1000))  # 25 mm/s: 25 mm per window
    assert _feed(LocalMinimumDetector(), slow, WALL)[0] is None
    settled = [0.004] * 1000  # at rest near the goal
    assert _feed(LocalMinimumDetector(), settled, WALL)[0] is None
    stalled = [0.1] * 1000  # stalled, but no obstacle acts (another cause: not ours to name)
    assert _feed(LocalMinimumDetector(), stalled, ())[0] is None
    assert _feed(LocalMinimumDetector(), stalled, (Influence("wall", "link5", 0.2, 0.0),))[0] is None


def test_reset_starts_a_new_window() -> None:
    detector = LocalMinimumDetector()
    _feed(detector, [0.1] * 200, WALL)  # 0.8 s: not yet
    detector.reset()
    assert _feed(detector, [0.1] * 200, WALL)[0] is None


def _add(shape: ObstacleShape, **dims) -> AddObstacle:
    values = dict(radius_m=None, height_m=None, size_m=None)
    values.update(dims)
    return AddObstacle(
        name="thing",
        shape=shape,
        position_world=np.array([0.4, 0.1, 0.3]),
        rotation_world=np.eye(3),
        velocity_world_mps=np.array([0.0, -0.05, 0.0]),
        influence_m=0.05,
        gain_scale=2.0,
        span=SPAN,
        line=3,
        statement="OBSTACLE thing ...",
        **values,
    )


def test_obstacles_from_statements() -> None:
    ball = from_step(_add(ObstacleShape.SPHERE, radius_m=0.06), t_s=2.0)
    np.testing.assert_allclose(ball.half_extents_m, (0.06, 0.06, 0.06))
    np.testing.assert_allclose(ball.position_at(4.0), (0.4, 0.0, 0.3))  # 2 s at -50 mm/s in y
    assert ball.moving and ball.influence_m == 0.05 and ball.gain_scale == 2.0
    post = from_step(_add(ObstacleShape.CYLINDER, radius_m=0.04, height_m=0.6), t_s=0.0)
    np.testing.assert_allclose(post.half_extents_m, (0.04, 0.04, 0.3))
    wall = from_step(_add(ObstacleShape.BOX, size_m=np.array([0.02, 0.6, 0.4])), t_s=0.0)
    np.testing.assert_allclose(wall.half_extents_m, (0.01, 0.3, 0.2))
    assert wall.bounding_radius_m == pytest.approx(np.linalg.norm((0.01, 0.3, 0.2)))
    with pytest.raises(CosmosError, match="RADIUS"):
        from_step(_add(ObstacleShape.SPHERE), t_s=0.0)
    with pytest.raises(CosmosError, match="SIZE"):
        from_step(_add(ObstacleShape.BOX, size_m=np.array([0.02, -0.6, 0.4])), t_s=0.0)
