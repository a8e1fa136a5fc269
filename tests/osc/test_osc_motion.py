"""Motion commands (eq. 19-21, 36-37) and the timed minimum-jerk trajectory."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.motion import PoseTrajectory, goal_command, goal_velocity, min_jerk, tracking_command
from cosmos.osc.orientation import pose_error, so3_exp, so3_log


def test_goal_velocity_respects_both_limits_and_points_at_the_goal(rng):
    kp, kv = 100.0, 20.0
    for _ in range(200):
        error = rng.normal(scale=rng.choice([1e-3, 0.1, 2.0]), size=6)
        v = goal_velocity(error, kp, kv, max_speed=0.25, max_angular_speed=0.5)
        assert np.linalg.norm(v[:3]) <= 0.25 * (1 + 1e-12)
        assert np.linalg.norm(v[3:]) <= 0.5 * (1 + 1e-12)
        for part in (slice(0, 3), slice(3, 6)):  # parallel to x_d - x, same sense
            cosine = v[part] @ -error[part] / (np.linalg.norm(v[part]) * np.linalg.norm(error[part]))
            assert cosine == pytest.approx(1.0)
    small = np.array([1e-3, 0, 0, 0, 1e-3, 0])
    np.testing.assert_allclose(goal_velocity(small, kp, kv, 0.25, 0.5), -(kp / kv) * small)


def test_goal_command_is_eq20_and_eq37():
    error = np.array([0.5, 0, 0, 0, 0, 0.0])
    xd = np.array([0.1, 0.2, 0, 0, 0, 0.3])
    # Far from the goal: -kv (xd - nu xd_d) with nu xd_d = 0.25 m/s towards the goal (-x).
    f = goal_command(error, xd, kp=100.0, kv=20.0, max_speed=0.25, max_angular_speed=1.0)
    np.testing.assert_allclose(f, -20.0 * (xd - np.array([-0.25, 0, 0, 0, 0, 0])))
    f37 = goal_command(error, xd, 100.0, 20.0, 0.25, 1.0, xi_q=5.0)
    np.testing.assert_allclose(f37, f + 5.0 * xd)


def test_tracking_command_is_eq19_and_eq36(rng):
    e, xd, xd_d, xdd_d = (rng.normal(size=6) for _ in range(4))
    kp = rng.uniform(1, 100, 6)  # per-axis gains work too
    f = tracking_command(e, xd, xd_d, xdd_d, kp, 20.0)
    np.testing.assert_allclose(f, xdd_d - kp * e - 20.0 * (xd - xd_d))
    np.testing.assert_allclose(tracking_command(e, xd, xd_d, xdd_d, kp, 20.0, xi_q=3.0), f + 3.0 * xd)


def test_unit_mass_under_goal_command_moves_straight_at_the_speed_limit():
    # The decoupled end effector (eq. 18: xdd = F*_m) under eq. 20-21, integrated in closed loop.
    kp, kv, v_max, w_max, dt = 400.0, 40.0, 0.2, 0.5, 1e-3
    p, v = np.zeros(3), np.zeros(3)
    r, w = np.eye(3), np.zeros(3)
    goal_p, goal_r = np.array([0.3, -0.4, 0.0]), so3_exp(np.array([0.0, 2.0, 0.0]))
    speeds, off_line = [], []
    for _ in range(6000):
        e = pose_error(p, r, goal_p, goal_r)
        a = goal_command(e, np.concatenate([v, w]), kp, kv, v_max, w_max)
        v += a[:3] * dt
        w += a[3:] * dt
        p += v * dt
        r = so3_exp(w * dt) @ r
        speeds.append(np.linalg.norm(v))
        off_line.append(np.linalg.norm(np.cross(p, goal_p)) / np.linalg.norm(goal_p))
        axis = so3_log(r)
        if np.linalg.norm(axis) > 1e-6:
            assert abs(axis[0]) + abs(axis[2]) < 1e-9  # fixed rotation axis (y)
    assert max(speeds) <= v_max * 1.001
    assert max(speeds) >= v_max * 0.99  # it does cruise at the limit
    assert max(off_line) < 1e-9
    np.testing.assert_allclose(p, goal_p, atol=1e-6)
    assert np.linalg.norm(so3_log(goal_r @ r.T)) < 1e-6


def test_min_jerk_derivatives_match_finite_differences():
    duration, h = 2.0, 1e-6
    for t in np.linspace(0.01, 1.99, 40):
        s, sd, sdd = min_jerk(t, duration)
        assert sd == pytest.approx((min_jerk(t + h, duration)[0] - min_jerk(t - h, duration)[0]) / (2 * h))
        assert sdd == pytest.approx(
            (min_jerk(t + h, duration)[1] - min_jerk(t - h, duration)[1]) / (2 * h), abs=1e-6
        )
    assert min_jerk(0.0, duration) == (0.0, 0.0, 0.0)
    assert min_jerk(duration, duration) == (1.0, 0.0, 0.0)
    assert min_jerk(1.0, duration)[0] == pytest.approx(0.5)


def test_pose_trajectory_velocity_and_acceleration_match_finite_differences(rng):
    r0 = so3_exp(rng.normal(size=3))
    r1 = so3_exp(math.radians(170) * np.array([0.0, 0.6, 0.8])) @ r0
    traj = PoseTrajectory.between(np.zeros(3), r0, np.array([0.2, -0.1, 0.3]), r1, 1.5)
    h = 1e-5
    for t in np.linspace(0.05, 1.45, 15):
        now, ahead, behind = traj.sample(t), traj.sample(t + h), traj.sample(t - h)
        v_fd = (ahead.position - behind.position) / (2 * h)
        w_fd = so3_log(ahead.rotation_to_world @ behind.rotation_to_world.T) / (2 * h)
        np.testing.assert_allclose(now.velocity, np.concatenate([v_fd, w_fd]), atol=1e-6)
        np.testing.assert_allclose(now.acceleration, (ahead.velocity - behind.velocity) / (2 * h), atol=1e-5)
    end = traj.sample(2.0)
    np.testing.assert_allclose(end.position, [0.2, -0.1, 0.3], atol=1e-15)
    np.testing.assert_allclose(end.rotation_to_world, r1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(0.0).rotation_to_world, r0, atol=1e-15)
    with pytest.raises(ValueError, match="duration_s"):
        PoseTrajectory.between(np.zeros(3), r0, np.zeros(3), r0, 0.0)
