"""The search patterns of INSERT ... SEARCH against their analytic curves."""

from __future__ import annotations

import math

import numpy as np

from cosmos.osc.search import (
    LissajousPath,
    SearchTrajectory,
    SpiralPath,
    into_the_hole,
    spiral_angle_at,
    spiral_arc_length,
    toward_the_hole,
)

PITCH = 0.003
RADIUS = 0.008


def test_spiral_arc_length_matches_a_dense_polyline() -> None:
    """The closed-form arc length (and its Newton inverse) against a summed polyline: a wrong
    formula would time the spiral at the wrong tangential speed."""
    theta = np.linspace(0.0, 2.0 * math.pi * RADIUS / PITCH, 200_001)
    r = PITCH * theta / (2.0 * math.pi)
    polyline = float(np.sum(np.hypot(np.diff(r * np.cos(theta)), np.diff(r * np.sin(theta)))))
    assert math.isclose(spiral_arc_length(theta[-1], PITCH), polyline, rel_tol=1e-6)
    for length in (1e-5, 1e-3, 0.02, polyline):
        assert math.isclose(spiral_arc_length(spiral_angle_at(length, PITCH), PITCH), length, rel_tol=1e-9)


def test_spiral_trajectory_follows_r_equals_pitch_theta_over_2pi_at_its_speed() -> None:
    """Every sample lies on r = PITCH theta / 2 pi (theta unwrapped), the tool moves at the
    documented speed between the ramps (finite differences of positions, not the sample's
    own velocity), and the pattern ends at RADIUS: catches a wrong curve, speed or end."""
    lateral = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    start = np.array([0.6, 0.15, 0.3])
    speed = 0.01
    trajectory = SearchTrajectory.of(SpiralPath(RADIUS, PITCH), start, np.eye(3), lateral, speed)
    times = np.arange(0.0, trajectory.duration_s, 1e-3)
    points = np.array([trajectory.sample(float(t)).position for t in times]) - start
    assert np.allclose(points[:, 2], 0.0)
    r = np.hypot(points[:, 0], points[:, 1])
    theta = np.unwrap(np.arctan2(points[:, 1], points[:, 0]))
    outside = r > 1e-4  # the angle is ill defined at the centre
    theta -= theta[outside][0] - 2.0 * math.pi * r[outside][0] / PITCH  # the branch of the first point
    assert np.allclose(r[outside], PITCH * theta[outside] / (2.0 * math.pi), atol=2e-6)
    assert math.isclose(r[-1], RADIUS, abs_tol=1e-6)
    speeds = np.hypot(*np.diff(points[:, :2], axis=0).T) / 1e-3
    middle = (times[1:] > 0.5) & (times[1:] < trajectory.duration_s - 0.5)
    assert np.allclose(speeds[middle], speed, rtol=2e-3)
    sample = trajectory.sample(2.0)
    assert np.allclose(sample.velocity[:2], (points[2001, :2] - points[1999, :2]) / 2e-3, atol=1e-4)


def test_lissajous_stays_in_its_square_and_leaves_no_gap_wider_than_the_pitch() -> None:
    """The figure (r sin(a phi), r sin((a+1) phi)) stays within RADIUS on each axis, reaches
    it, and crosses the pattern's y axis at most PITCH apart: catches too few lobes."""
    path = LissajousPath.of(RADIUS, PITCH)
    points = np.array([path.at(s) for s in np.linspace(0.0, path.length_m, 20_000)])
    assert np.all(np.abs(points) <= RADIUS + 1e-9)
    assert np.max(points[:, 0]) > 0.99 * RADIUS and np.max(points[:, 1]) > 0.99 * RADIUS
    x = points[:, 0]
    crossings = np.flatnonzero(np.sign(x[1:]) != np.sign(x[:-1]))
    levels = np.unique(np.round(points[crossings, 1], 5))
    assert np.max(np.diff(levels)) <= PITCH
    phi = np.linspace(0.0, 2.0 * math.pi, 10)
    a = path.lobes
    expected = np.column_stack((RADIUS * np.sin(a * phi), RADIUS * np.sin((a + 1) * phi)))
    lengths = np.interp(phi, path.phi, path.arc_m)
    assert np.allclose([path.at(s) for s in lengths], expected, atol=1e-7)


def test_toward_the_hole_points_at_the_tipped_part_s_lowest_rim() -> None:
    """The direction a tipped part's rim went down, from the rim itself: for random tilts up to 15 deg
    of a tool-down peg and of one inserting along world +x, the rim point deepest along the
    insertion lies along the returned direction from the tip, and the size is the tilt's sine.
    Catches a sign error (the lead would push the peg away from the hole) or a frame mix-up."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(7)
    rim = np.array([(math.cos(a), math.sin(a), 0.0) for a in np.linspace(0.0, 2.0 * math.pi, 3601)])
    starts = {
        "down": (Rotation.from_euler("x", 180.0, degrees=True).as_matrix(), np.eye(3)[:, :2]),
        "+x": (Rotation.from_euler("y", 90.0, degrees=True).as_matrix(), np.eye(3)[:, 1:]),
    }
    for start, lateral in starts.values():
        n = start[:, 2]  # the peg's axis, tool z, is the insertion direction
        for _ in range(20):
            axis = lateral.dot(rng.normal(size=2))
            angle = math.radians(rng.uniform(1.0, 15.0))
            rotation = Rotation.from_rotvec(angle * axis / np.linalg.norm(axis)).as_matrix().dot(start)
            toward, size = toward_the_hole(rotation, start, n, lateral)
            deepest = rotation.dot(rim[int(np.argmax(rotation.dot(rim.T).T.dot(n)))])
            bearing = lateral.dot(lateral.T.dot(deepest))
            assert float(toward.dot(bearing / np.linalg.norm(bearing))) > math.cos(math.radians(0.2))
            assert math.isclose(size, math.sin(angle), rel_tol=1e-9)
    untipped, size = toward_the_hole(
        starts["down"][0], starts["down"][0], np.array((0.0, 0, -1)), np.eye(3)[:, :2]
    )
    assert size == 0.0 and not untipped.any()


def test_a_lead_creeping_toward_the_hole_makes_its_way_in() -> None:
    """A Panda's lead 1 s after the find (tests/run/test_run_search_lead.py, run 0): the tip went
    from (3.42, -5.26) mm to (2.92, -4.41) mm off the hole's axis and 0.31 mm deeper. Its way in,
    across toward the hole the find pointed at plus deeper, is the shrink of its distance to the
    axis (hypot, not a projection) plus the depth: 1.30 mm, over the jam check's 0.5 mm in 1 s,
    which the depth alone is not. Catches a lead judged on depth alone (it failed that run
    "jammed at depth 0.5 mm") or on its travel across with the wrong sign; beyond the search's
    RADIUS only the depth counts."""
    down = np.array((0.0, 0.0, -1.0))
    before = np.array((3.42e-3, -5.26e-3, 0.0))
    after = np.array((2.92e-3, -4.41e-3, -0.31e-3))
    toward = -before / np.linalg.norm(before)  # the tilt's bearing: within 0.5 deg of the hole's
    made = into_the_hole(after - before, toward, down)
    shrink = math.hypot(*before[:2]) - math.hypot(*after[:2])
    assert math.isclose(made, shrink + 0.31e-3, rel_tol=1e-2)
    assert made > 0.5e-3 > 0.31e-3
    assert math.isclose(into_the_hole(before - after, toward, down), -made)
    assert math.isclose(into_the_hole(after - before, toward, down, across_counts=False), 0.31e-3)
