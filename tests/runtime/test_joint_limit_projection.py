"""The joint limits' task projection and constraint: kernels against cosmos.osc.limits, and what they mean."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.dynamics import TRANSLATION_GIVE_UP
from cosmos.osc.limits import joint_limit_constraint, joint_limit_task_projection
from cosmos.runtime.kernels.limits import joint_limit_constraint_into, joint_limit_projection_into
from cosmos.runtime.kernels.parameter import fold_servo

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
        joint_limit_projection_into(got, jacobian, q, LOWER, UPPER, direction, MARGIN, WHOLE, np.zeros(6))
        np.testing.assert_allclose(got, expected, atol=1e-12)
        # Away from the limit nothing is removed.
        away = np.eye(6)
        joint_limit_projection_into(away, jacobian, q, LOWER, UPPER, -direction, MARGIN, WHOLE, np.zeros(6))
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


# --- a redundant arm: the task without the joint (J N_c) ---------------------------------------

N7 = 7
LOWER7, UPPER7 = np.full(N7, -2.0), np.full(N7, 2.0)
LIMITS7 = (LOWER7, UPPER7)


def _arm7(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A random 7-joint arm: A^-1 (symmetric positive definite) and J. # (7, 7), (6, 7)"""
    root = rng.normal(size=(N7, N7))
    inertia = root @ root.T + N7 * np.eye(N7)
    return np.linalg.inv(inertia), rng.normal(size=(6, N7))


def _driven(inertia_inv: np.ndarray, jacobian: np.ndarray, direction: np.ndarray, joint: int) -> float:
    """The sign joint ``joint`` turns toward the goal through Jbar (eq. 28)."""
    lambda_ = np.linalg.inv(jacobian @ inertia_inv @ jacobian.T)
    return float(np.sign((inertia_inv @ jacobian.T @ lambda_ @ direction)[joint]))


def _q_at(rng: np.random.Generator, sign: float, joint: int, distance: float) -> np.ndarray:
    q = rng.uniform(-1.0, 1.0, N7)
    q[joint] = UPPER7[joint] - distance if sign > 0.0 else LOWER7[joint] + distance
    return q


def test_constraint_kernel_matches_the_reference() -> None:
    """Joint 3 (and then also joint 6) at 0.05-0.35 rad from the limit the goal drives it into:
    the compiled N_c equals cosmos.osc.limits.joint_limit_constraint, and a joint driven away from
    its limit is not constrained. Catches the soft weight inverted, the wrong column of A^-1, or
    the goal's direction taken through J^+ instead of Jbar."""
    rng = np.random.default_rng(21)
    for distance in (0.05, 0.15, 0.2, 0.29, 0.35):
        for joints in ((2,), (2, 5)):
            inertia_inv, jacobian = _arm7(rng)
            direction = rng.normal(size=6)
            q = rng.uniform(-1.0, 1.0, N7)
            for joint in joints:
                sign = _driven(inertia_inv, jacobian, direction, joint)
                q[joint] = _q_at(rng, sign, joint, distance)[joint]
            expected = joint_limit_constraint(inertia_inv, jacobian, q, *LIMITS7, direction, MARGIN, WHOLE)
            got = np.eye(N7)
            changed = joint_limit_constraint_into(
                got, inertia_inv, jacobian, q, LOWER7, UPPER7, direction, MARGIN, WHOLE
            )
            np.testing.assert_allclose(got, expected, atol=1e-12)
            assert changed == (distance < MARGIN)
            away = np.eye(N7)
            joint_limit_constraint_into(away, inertia_inv, jacobian, q, *LIMITS7, -direction, MARGIN, WHOLE)
            if len(joints) == 1:
                np.testing.assert_array_equal(away, np.eye(N7))


def test_the_task_without_a_joint_at_its_limit_is_the_least_energy_motion_without_it() -> None:
    """Joint 3 within WHOLE of its limit: the torques ``N_c^T J^T Lambda_c F`` give the tool exactly
    F and joint 3 no acceleration, the least kinetic-energy acceleration doing so (compared with a
    KKT solve of min qdd^T A qdd, J qdd = F, qdd_3 = 0); half-way in, joint 3 keeps half its share
    (``e_3^T N_c = (1 - g) e_3^T``) and ``N_c A^-1`` stays symmetric. Catches N_c built with A
    instead of A^-1 (not dynamically consistent: the tool misses F) or the weight applied twice."""
    rng = np.random.default_rng(22)
    inertia_inv, jacobian = _arm7(rng)
    direction = rng.normal(size=6)
    q = _q_at(rng, _driven(inertia_inv, jacobian, direction, 2), 2, 0.1)
    constraint = joint_limit_constraint(inertia_inv, jacobian, q, *LIMITS7, direction, MARGIN, WHOLE)
    task = jacobian @ constraint
    lambda_c = np.linalg.inv(jacobian @ inertia_inv @ task.T)
    force = rng.normal(size=6)
    acceleration = inertia_inv @ task.T @ lambda_c @ force
    inertia = np.linalg.inv(inertia_inv)
    rows = np.vstack((jacobian, np.eye(N7)[2]))
    kkt = np.block([[inertia, rows.T], [rows, np.zeros((7, 7))]])
    expected = np.linalg.solve(kkt, np.concatenate((np.zeros(N7), force, [0.0])))[:N7]
    np.testing.assert_allclose(acceleration, expected, atol=1e-9)
    np.testing.assert_allclose(jacobian @ acceleration, force, atol=1e-9)
    half = _q_at(rng, _driven(inertia_inv, jacobian, direction, 2), 2, 0.5 * (MARGIN + WHOLE))
    half[[0, 1, 3, 4, 5, 6]] = q[[0, 1, 3, 4, 5, 6]]
    soft = joint_limit_constraint(inertia_inv, jacobian, half, *LIMITS7, direction, MARGIN, WHOLE)
    np.testing.assert_allclose(soft[2], 0.5 * np.eye(N7)[2], atol=1e-12)
    np.testing.assert_allclose(soft @ inertia_inv, (soft @ inertia_inv).T, atol=1e-12)


def test_the_fold_leaves_the_constrained_joint_to_the_null_space() -> None:
    """fold_servo with the task through J N_c (joint 3 within WHOLE of its limit): a torque through
    the null space (``N^T`` of the fold) gives the tool no acceleration (``J A^-1 N^T = 0``) but
    joint 3 all of it (``e_3^T A^-1 N^T e_3 = (A^-1)_33``): the joint-limit potential acts on the
    joint, not the tool; and eq. 34's damping block slows joint 3 alone at xi_q
    (``e_3^T A^-1 D = -xi_q e_3^T``). Catches N^T formed with J' on both sides (then the
    potential's torque on joint 3 would be absorbed or reach the tool)."""
    rng = np.random.default_rng(23)
    inertia_inv, jacobian = _arm7(rng)
    inertia = np.linalg.inv(inertia_inv)
    direction = rng.normal(size=6)
    q = _q_at(rng, _driven(inertia_inv, jacobian, direction, 2), 2, 0.1)
    task = jacobian @ joint_limit_constraint(inertia_inv, jacobian, q, *LIMITS7, direction, MARGIN, WHOLE)
    zero, xi_q = np.zeros(N7), 20.0
    stacked, null_space_t = np.zeros((N7, 19 + N7)), np.zeros((N7, N7))
    out = [np.zeros((6, 6)), np.zeros((N7, 6)), np.zeros((6, 6))]
    fold_servo(
        inertia, inertia_inv, jacobian, task, zero, zero, np.zeros(6), zero, np.eye(6), np.zeros((6, 6)),
        30.0, xi_q, zero, 0.02, 1e9, 1.0, 0.5, stacked, *out, np.eye(6), null_space_t,
    )  # fmt: skip
    np.testing.assert_allclose(jacobian @ inertia_inv @ null_space_t, np.zeros((6, N7)), atol=1e-9)
    assert (inertia_inv @ null_space_t)[2, 2] == pytest.approx(inertia_inv[2, 2], rel=1e-9)
    np.testing.assert_allclose((inertia_inv @ stacked[:, 19:])[2], -xi_q * np.eye(N7)[2], atol=1e-9)
