"""so(3) exp/log, Jacobians, quaternions and RPY against Pinocchio and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from cosmos.osc.orientation import (
    matrix_to_quat,
    pose_error,
    quat_to_matrix,
    rotation_difference,
    rpy_to_matrix,
    so3_exp,
    so3_left_jacobian,
    so3_left_jacobian_inverse,
    so3_log,
)

ANGLES_DEG = [0.0, 1e-7, 1e-3, 0.5, 30.0, 90.0, 150.0, 175.0, 179.0, 179.9, 179.999, 180.0]


def random_axis(rng: np.random.Generator) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("angle_deg", ANGLES_DEG)
def test_exp_matches_pinocchio_and_log_round_trips(rng, angle_deg):
    for _ in range(20):
        v = math.radians(angle_deg) * random_axis(rng)
        r = so3_exp(v)
        np.testing.assert_allclose(r, pin.exp3(v), atol=1e-14)
        w = so3_log(r)
        np.testing.assert_allclose(so3_exp(w), r, atol=1e-12)
        assert abs(np.linalg.norm(w) - math.radians(angle_deg)) < 1e-9
        if angle_deg < 179.0:  # unique log: the same vector back
            np.testing.assert_allclose(w, v, atol=1e-10)


def test_log_at_pi_of_a_nearly_orthogonal_matrix_is_finite_and_right(rng):
    for _ in range(50):
        v = math.pi * random_axis(rng)
        r = so3_exp(v) + rng.normal(scale=1e-13, size=(3, 3))
        w = so3_log(r)
        assert np.all(np.isfinite(w))
        np.testing.assert_allclose(so3_exp(w), r, atol=1e-9)


@pytest.mark.parametrize("angle_deg", [0.0, 20.0, 120.0, 179.0])
def test_left_jacobian_is_the_derivative_of_exp(rng, angle_deg):
    # d/dt exp(v(t)) = [J_l(v) vdot]x exp(v): compare the world angular velocity.
    for _ in range(10):
        v = math.radians(angle_deg) * random_axis(rng)
        vdot = rng.normal(size=3)
        h = 1e-6
        r_plus, r_minus = so3_exp(v + h * vdot), so3_exp(v - h * vdot)
        omega_fd = so3_log(r_plus @ r_minus.T) / (2 * h)
        np.testing.assert_allclose(so3_left_jacobian(v) @ vdot, omega_fd, atol=1e-7)


@pytest.mark.parametrize("angle_deg", [0.0, 20.0, 120.0, 170.0, 179.0])
def test_inverse_left_jacobian_is_the_derivative_of_log(rng, angle_deg):
    for _ in range(10):
        v = math.radians(angle_deg) * random_axis(rng)
        omega = rng.normal(size=3)
        r = so3_exp(v)
        h = 1e-7
        vdot_fd = (so3_log(so3_exp(h * omega) @ r) - so3_log(so3_exp(-h * omega) @ r)) / (2 * h)
        np.testing.assert_allclose(so3_left_jacobian_inverse(v) @ omega, vdot_fd, atol=2e-6)
        np.testing.assert_allclose(so3_left_jacobian_inverse(v) @ so3_left_jacobian(v), np.eye(3), atol=1e-12)
        # Pinocchio's Jlog3 is the right Jacobian: J_r^{-1} = J_l^{-T}.
        np.testing.assert_allclose(pin.Jlog3(r), so3_left_jacobian_inverse(v).T, atol=1e-9)


def test_quaternion_round_trip_and_pinocchio(rng):
    for _ in range(200):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        r = quat_to_matrix(q)
        pq = pin.Quaternion(q[0], q[1], q[2], q[3])  # Pinocchio's constructor is (w, x, y, z)
        np.testing.assert_allclose(r, pq.toRotationMatrix(), atol=1e-14)
        back = matrix_to_quat(r)
        assert back[0] >= 0.0
        np.testing.assert_allclose(back, q * np.sign(q[0]), atol=1e-12)
    # Non-unit input is normalised.
    np.testing.assert_allclose(quat_to_matrix(np.array([2.0, 0, 0, 0])), np.eye(3))


def test_matrix_to_quat_at_half_turns():
    for axis in np.eye(3):
        r = so3_exp(math.pi * axis)
        np.testing.assert_allclose(quat_to_matrix(matrix_to_quat(r)), r, atol=1e-14)


def test_rpy_is_fixed_axis_zyx_and_matches_pinocchio(rng):
    for _ in range(100):
        roll, pitch, yaw = rng.uniform(-math.pi, math.pi, 3)
        r = rpy_to_matrix(roll, pitch, yaw)
        np.testing.assert_allclose(r, pin.rpy.rpyToMatrix(roll, pitch, yaw), atol=1e-14)
        expected = so3_exp(yaw * np.eye(3)[2]) @ so3_exp(pitch * np.eye(3)[1]) @ so3_exp(roll * np.eye(3)[0])
        np.testing.assert_allclose(r, expected, atol=1e-14)
    # The language's "tool pointing down": RPY (180 deg, 0, 0) flips z.
    np.testing.assert_allclose(rpy_to_matrix(math.pi, 0, 0) @ [0, 0, 1], [0, 0, -1], atol=1e-15)


def test_rotation_difference_is_zero_iff_equal_and_takes_b_to_a(rng):
    for angle_deg in [1e-6, 10.0, 90.0, 179.0]:
        r_b = so3_exp(rng.normal(size=3))
        r_a = so3_exp(math.radians(angle_deg) * random_axis(rng)) @ r_b
        e = rotation_difference(r_a, r_b)
        assert np.linalg.norm(e) > 0.0
        np.testing.assert_allclose(so3_exp(e) @ r_b, r_a, atol=1e-12)
        assert np.linalg.norm(rotation_difference(r_b, r_b)) < 1e-15


def test_pose_error_is_x_minus_xd_and_linear_in_the_angle(rng):
    r_d = so3_exp(rng.normal(size=3))
    axis = random_axis(rng)
    for angle_deg in [5.0, 90.0, 179.0]:
        r = so3_exp(math.radians(angle_deg) * axis) @ r_d
        e = pose_error(np.array([1.0, 2, 3]), r, np.array([0.5, 2, 4]), r_d)
        np.testing.assert_allclose(e[:3], [0.5, 0, -1])
        # Linear in the angle: no saturation (the quaternion vector part would give 2 sin(t/2)).
        np.testing.assert_allclose(e[3:], math.radians(angle_deg) * axis, atol=1e-12)
