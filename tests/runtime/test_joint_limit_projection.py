"""The joint limits' task projection: compiled kernel against cosmos.osc.limits, and what it means."""

from __future__ import annotations

import numpy as np

from cosmos.osc.dynamics import TRANSLATION_GIVE_UP
from cosmos.osc.limits import joint_limit_task_projection
from cosmos.runtime.kernels.parameter import joint_limit_projection_into

MARGIN, WHOLE = 0.30, 0.15
LOWER, UPPER = np.full(6, -2.0), np.full(6, 2.0)


def _case(rng: np.random.Generator, distance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    jacobian = 0.6 * np.eye(6) + rng.normal(0.0, 0.2, (6, 6))
    q = rng.uniform(-1.0, 1.0, 6)
    direction = rng.normal(size=6)
    rates = np.linalg.solve(jacobian, direction)
    q[2] = UPPER[2] - distance if rates[2] > 0.0 else LOWER[2] + distance  # joint 3 driven into a limit
    return jacobian, q, direction


def test_kernel_matches_the_reference() -> None:
    """Joint 3 at 0.05-0.35 rad from the limit the goal drives it into (outside, ramping, whole),
    others far: the compiled projection equals the NumPy one. Catches the weight's ramp inverted,
    the wrong row of J^-1, or a joint moving away from its limit treated as blocked."""
    rng = np.random.default_rng(11)
    for distance in (0.05, 0.15, 0.2, 0.29, 0.35):
        jacobian, q, direction = _case(rng, distance)
        expected = joint_limit_task_projection(
            jacobian, q, LOWER, UPPER, direction, MARGIN, WHOLE, TRANSLATION_GIVE_UP
        )
        got = np.eye(6)
        joint_limit_projection_into(got, jacobian, q, LOWER, UPPER, direction, MARGIN, WHOLE)
        np.testing.assert_allclose(got, expected, atol=1e-12)
        # Away from the limit nothing is removed.
        away = np.eye(6)
        joint_limit_projection_into(away, jacobian, q, LOWER, UPPER, -direction, MARGIN, WHOLE)
        np.testing.assert_allclose(away, np.eye(6), atol=1e-12)


def test_a_joint_at_its_limit_gets_no_share_of_the_command() -> None:
    """Within WHOLE of the limit, the projected command moves joint 3 not at all (J^-1 P t has no
    joint-3 component) and keeps the translation (to TRANSLATION_GIVE_UP). Catches a projection
    along u itself (which bends the translation) or one that leaves joint 3 driven."""
    rng = np.random.default_rng(12)
    jacobian, q, direction = _case(rng, 0.1)
    projection = joint_limit_task_projection(
        jacobian, q, LOWER, UPPER, direction, MARGIN, WHOLE, TRANSLATION_GIVE_UP
    )
    for _ in range(10):
        command = rng.normal(size=6)
        projected = projection @ command
        assert abs(np.linalg.solve(jacobian, projected)[2]) < 1e-9
        np.testing.assert_allclose(projected[:3], command[:3], atol=0.05 * np.linalg.norm(command))
