"""Each joint's Coulomb friction error, learnt (cosmos.osc.friction.adapt_coulomb_error), and its kernel.

The compiled kernel (cosmos.runtime.kernels.friction_adaptation) against the readable reference
on seeded random inputs, and the reference against the update worked by hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.friction import COULOMB_ADAPTATION_RATE_PER_S, COULOMB_ERROR_RANGE, adapt_coulomb_error
from cosmos.runtime.kernels.friction_adaptation import adapted_levels

DT_S = 0.001
KV, LOOKAHEAD_S, FULL_SPEED_RAD_S = 40.0, 0.02, 0.01
POSITIVE_NM = np.array([24.73, 13.58, 7.09, 0.85, 0.67, 0.30])
NEGATIVE_NM = np.array([27.24, 7.65, 5.64, 1.29, 1.04, 0.81])


def test_a_joint_the_servo_pushes_along_its_motion_is_compensated_more() -> None:
    """Catches a sign slip in the update (a joint the servo helps along its motion is
    under-compensated: its error must rise; one it holds back, fall), the wrong direction's level,
    a joint at rest learning, and the bound not holding: against the update worked by hand."""
    reference = np.array([0.02, -0.004, 0.0, 0.02, -0.02, 0.005])  # [rad/s]: full, 0.4 of it, at rest
    torque = np.array([2.0, -1.5, 3.0, -0.5, -4.0, 0.1])  # [N m]
    error = np.array([0.0, 0.0, 0.0, 0.0, 0.099, -0.099])
    new = adapt_coulomb_error(error, reference, torque, POSITIVE_NM, NEGATIVE_NM, FULL_SPEED_RAD_S, DT_S)
    r = COULOMB_ADAPTATION_RATE_PER_S
    assert new[0] == pytest.approx(r * 1.0 * 2.0 / 24.73 * DT_S)  # pushed on along +: up, by Gamma_c(+)
    assert new[1] == pytest.approx(r * -0.4 * -1.5 / 7.65 * DT_S)  # pushed on along -: up, by Gamma_c(-)
    assert new[2] == 0.0  # told to stay: its torque is not its friction
    assert new[3] == pytest.approx(r * 1.0 * -0.5 / 0.85 * DT_S)  # held back along +: down
    assert new[4] == COULOMB_ERROR_RANGE  # pushed on along -, at the bound
    assert new[5] == pytest.approx(-0.099 + r * 0.5 * 0.1 / 0.30 * DT_S)


@pytest.mark.parametrize("adapt", [True, False])
def test_the_compiled_levels_match_the_reference(adapt: bool) -> None:
    """Catches the compiled kernel drifting from cosmos.osc.friction.adapt_coulomb_error: the
    reference motion ``Jbar v_r`` with ``v_r = xd + F*_fb / kv``, the feedback's torques
    ``J^T Lambda F*_fb``, the levels scaled by ``1 + eps``, and learning only when told to."""
    rng = np.random.default_rng(31)
    for _ in range(50):
        jbar = rng.normal(0.0, 2.0, (6, 6))
        to_torque = rng.normal(0.0, 5.0, (6, 6))
        stacked = np.zeros((6, 25))
        stacked[:, :6] = to_torque
        stacked[:, 6:] = rng.normal(size=(6, 19))  # the other columns must not count
        fed_back = rng.normal(0.0, 0.2, 6)
        velocity = rng.normal(0.0, 0.01, 6)
        error = rng.uniform(-COULOMB_ERROR_RANGE, COULOMB_ERROR_RANGE, 6)
        gains = np.array((KV, LOOKAHEAD_S, 1.0 / FULL_SPEED_RAD_S, DT_S))
        compiled = error.copy()
        levels = adapted_levels(
            compiled,
            fed_back,
            velocity,
            stacked,
            LOOKAHEAD_S * jbar,
            (POSITIVE_NM, NEGATIVE_NM),
            adapt,
            gains,
        )
        expected = error
        if adapt:
            reference = jbar @ (velocity + fed_back / KV)
            expected = adapt_coulomb_error(
                error, reference, to_torque @ fed_back, POSITIVE_NM, NEGATIVE_NM, FULL_SPEED_RAD_S, DT_S
            )
        assert compiled == pytest.approx(expected, rel=1e-9, abs=1e-12)
        assert levels[0] == pytest.approx((1.0 + expected) * POSITIVE_NM, rel=1e-9)
        assert levels[1] == pytest.approx((1.0 + expected) * NEGATIVE_NM, rel=1e-9)
