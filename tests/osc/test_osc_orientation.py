"""so(3) exp/log, quaternions and RPY against Pinocchio and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from cosmos.osc.orientation import (
    matrix_to_quat,
    pose_error,
    so3_exp,
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


def _pinocchio_matrix(q: np.ndarray) -> np.ndarray:
    """The rotation of a unit quaternion (w, x, y, z), by Pinocchio (its constructor is (w, x, y, z))."""
    return pin.Quaternion(q[0], q[1], q[2], q[3]).toRotationMatrix()


def test_matrix_to_quat_is_pinocchios_quaternion(rng):
    """Catches a quaternion with the wrong order of parts, the wrong hemisphere or the wrong branch."""
    for _ in range(200):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        back = matrix_to_quat(_pinocchio_matrix(q))
        assert back[0] >= 0.0
        np.testing.assert_allclose(back, q * np.sign(q[0]), atol=1e-12)


def test_matrix_to_quat_at_half_turns():
    for axis in np.eye(3):
        r = so3_exp(math.pi * axis)
        np.testing.assert_allclose(_pinocchio_matrix(matrix_to_quat(r)), r, atol=1e-14)


def test_pose_error_is_x_minus_xd_and_linear_in_the_angle(rng):
    r_d = so3_exp(rng.normal(size=3))
    axis = random_axis(rng)
    for angle_deg in [5.0, 90.0, 179.0]:
        r = so3_exp(math.radians(angle_deg) * axis) @ r_d
        e = pose_error(np.array([1.0, 2, 3]), r, np.array([0.5, 2, 4]), r_d)
        np.testing.assert_allclose(e[:3], [0.5, 0, -1])
        # Linear in the angle: no saturation (the quaternion vector part would give 2 sin(t/2)).
        np.testing.assert_allclose(e[3:], math.radians(angle_deg) * axis, atol=1e-12)
