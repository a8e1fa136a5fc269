"""Torque saturation and the joint-limit potential."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.firas import firas_potential
from cosmos.osc.limits import joint_limit_torque, saturate_torque

TORQUE_MAX = np.array([97.6, 186.4, 89.4, 24.2, 20.1, 21.3])


def test_saturation_keeps_gravity_and_the_direction_of_the_rest(rng):
    for _ in range(200):
        gravity = rng.uniform(-0.5, 0.5, 6) * TORQUE_MAX
        tau = gravity + rng.normal(scale=rng.choice([1.0, 50.0, 500.0]), size=6)
        out, scale = saturate_torque(tau, TORQUE_MAX, keep=gravity)
        assert np.all(np.abs(out) <= TORQUE_MAX * (1 + 1e-12))
        np.testing.assert_allclose(out - gravity, scale * (tau - gravity), atol=1e-9)
        if np.all(np.abs(tau) <= TORQUE_MAX):
            assert scale == 1.0 and out is tau
        else:  # the largest feasible scale: some joint sits on its limit
            assert np.isclose(np.abs(out), TORQUE_MAX).any()


def test_saturation_without_keep_scales_the_whole_command():
    tau = np.array([200.0, 0, 0, 10.0, 0, 0])
    out, scale = saturate_torque(tau, TORQUE_MAX)
    assert scale == pytest.approx(97.6 / 200.0)
    np.testing.assert_allclose(out, scale * tau)


def test_saturation_clips_an_infeasible_kept_part():
    gravity = np.array([0.0, 250.0, 0, 0, 0, 0])
    out, scale = saturate_torque(gravity + 1.0, TORQUE_MAX, keep=gravity)
    assert out[1] == pytest.approx(186.4) and scale == 0.0


def test_joint_limit_torque_is_the_negative_gradient_of_the_potential():
    q_min, q_max = np.full(6, -1.0), np.full(6, 1.0)
    rho_0, eta = 0.2, 1e-3
    q = np.array([-0.95, -0.85, 0.0, 0.79, 0.9, 0.99])

    def potential(qq):
        total = 0.0
        for rho in np.concatenate([qq - q_min, q_max - qq]):
            total += float(firas_potential(rho, rho_0, eta))
        return total

    h = 1e-7
    gradient = np.array([(potential(q + h * e) - potential(q - h * e)) / (2 * h) for e in np.eye(6)])
    np.testing.assert_allclose(joint_limit_torque(q, q_min, q_max, rho_0, eta, 1e9), -gradient, rtol=1e-5)
    tau = joint_limit_torque(q, q_min, q_max, rho_0, eta, 1e9)
    assert tau[0] > 0 and tau[1] > 0 and tau[4] < 0 and tau[5] < 0  # pushed away from the limits
    assert tau[2] == 0.0 and tau[3] == 0.0  # outside rho_0


def test_joint_limit_torque_is_capped_at_and_beyond_the_limit():
    q_min, q_max = np.full(2, -1.0), np.full(2, 1.0)
    tau = joint_limit_torque(np.array([-1.0, 1.5]), q_min, q_max, 0.2, 1e-3, 30.0)
    np.testing.assert_allclose(tau, [30.0, -30.0])
