"""The selection matrices of Figure 2."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.force import selection, task_diagonal_to_world
from cosmos.osc.orientation import rpy_to_matrix, so3_exp


@pytest.mark.parametrize("axes", [(1, 1, 1, 1, 1, 1), (1, 1, 0, 1, 1, 1), (0, 0, 1, 1, 0, 1), (0,) * 6])
def test_selection_matrices_are_complementary_projectors(rng, axes):
    r = so3_exp(rng.normal(size=3))
    omega, omega_bar = selection([bool(a) for a in axes], r)
    np.testing.assert_allclose(omega + omega_bar, np.eye(6), atol=1e-15)
    for p in (omega, omega_bar):
        np.testing.assert_allclose(p @ p, p, atol=1e-14)
        np.testing.assert_allclose(p, p.T, atol=1e-15)
    np.testing.assert_allclose(omega @ omega_bar, 0.0, atol=1e-14)
    assert np.trace(omega) == pytest.approx(sum(axes))


def test_selection_rotates_with_the_task_frame(rng):
    axes = (True, False, True, False, True, True)
    r = so3_exp(rng.normal(size=3))
    omega_world, _ = selection(axes, np.eye(3))
    omega, _ = selection(axes, r)
    big_r = np.kron(np.eye(2), r)  # blkdiag(R, R)
    np.testing.assert_allclose(omega, big_r @ omega_world @ big_r.T, atol=1e-14)


def test_a_force_axis_of_a_tilted_frame_is_its_rotated_z():
    # Task frame tilted 30 deg about world x; force control along its z, motion elsewhere.
    r = rpy_to_matrix(math.radians(30), 0.0, 0.0)
    omega, omega_bar = selection([True, True, False, True, True, True], r)
    z_task = r[:, 2]
    np.testing.assert_allclose(omega_bar[:3, :3], np.outer(z_task, z_task), atol=1e-15)
    np.testing.assert_allclose(omega[:3, :3] @ z_task, 0.0, atol=1e-15)
    np.testing.assert_allclose(omega[3:, 3:], np.eye(3), atol=1e-15)


def test_task_diagonal_to_world_is_blockwise_r_diag_rt(rng):
    values = rng.uniform(1, 5, 6)
    r = so3_exp(rng.normal(size=3))
    out = task_diagonal_to_world(values, r)
    np.testing.assert_allclose(out[:3, :3], r @ np.diag(values[:3]) @ r.T, atol=1e-14)
    np.testing.assert_allclose(out[3:, 3:], r @ np.diag(values[3:]) @ r.T, atol=1e-14)
    np.testing.assert_allclose(out[:3, 3:], 0.0)


def test_selection_rejects_a_wrong_axis_count():
    with pytest.raises(ValueError, match="6 entries"):
        selection([True] * 5, np.eye(3))
