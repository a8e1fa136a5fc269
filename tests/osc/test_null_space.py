"""The null-space objectives (cosmos.osc.null_space, cosmos.runtime.null_space) on the PUMA's position task.

The checks are the properties eq. 28 and 34 promise, computed apart: a torque
``N^T Gamma`` gives the tool point no acceleration (``J A^-1 N^T Gamma = 0``), and
the split ``N^T Gamma + J^T Jbar^T Gamma`` is ``Gamma``.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from cosmos.osc.dynamics import operational_dynamics
from cosmos.osc.null_space import (
    DEFAULT_ABSORPTION,
    absorbed_weight,
    posture_torque,
    task_lambda_inverse,
    through_null_space,
)
from cosmos.robot_model import build_robot_model
from cosmos.runtime.null_space import LinkField, NullSpaceTerms
from cosmos.runtime.parameters import ParameterLevel

ROBOT = build_robot_model()
Q = np.array((0.1, 0.7, -2.9, 0.3, -0.8, 2.8))


def position_task(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(A, J_position, N^T)`` at ``q``: the 3-row tool-point task of eq. 27-28."""
    model, data = ROBOT.model, ROBOT.model.createData()
    inertia = pin.crba(model, data, q)
    inertia = np.triu(inertia) + np.triu(inertia, 1).T
    jacobian = pin.computeFrameJacobian(model, data, q, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)[:3]
    zero = np.zeros(len(q))
    dynamics = operational_dynamics(inertia, jacobian, zero, zero, np.zeros(3))
    return inertia, jacobian, dynamics.null_space_t


def test_the_free_rows_cut_from_lambda_leave_the_position_task() -> None:
    """task_lambda_inverse, inverted and cut by C, is Lambda_r of the 3-row task (eq. 27). Catches
    the free rows' inverse mass leaking into the controlled block (C not a projector's use)."""
    inertia, jacobian_p, _ = position_task(Q)
    model, data = ROBOT.model, ROBOT.model.createData()
    jacobian = pin.computeFrameJacobian(model, data, Q, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)
    lambda_inv = jacobian @ np.linalg.solve(inertia, jacobian.T)
    controlled = np.diag((1.0, 1.0, 1.0, 0.0, 0.0, 0.0))
    cut = controlled @ np.linalg.inv(task_lambda_inverse(lambda_inv, controlled)) @ controlled
    expected = np.linalg.inv(jacobian_p @ np.linalg.solve(inertia, jacobian_p.T))
    np.testing.assert_allclose(cut[:3, :3], expected, rtol=1e-9)
    assert not cut[3:].any() and not cut[:, 3:].any()


@pytest.mark.parametrize("weight", [0.0, 0.4, 1.0])
def test_through_null_space_hides_the_absorbed_share_from_the_tool(weight: float) -> None:
    """``J A^-1`` of the applied torque is ``(1 - w)`` of the raw one's: w = 1 leaves the tool
    unaccelerated (eq. 34), w = 0 applies Gamma whole. Catches N used for N^T, and the weight
    applied to the null-space part instead of the part that reaches the tool."""
    inertia, jacobian, null_space_t = position_task(Q)
    torque = np.random.default_rng(4).normal(0.0, 10.0, len(Q))
    applied = through_null_space(torque, null_space_t, weight)
    raw = jacobian @ np.linalg.solve(inertia, torque)
    np.testing.assert_allclose(jacobian @ np.linalg.solve(inertia, applied), (1.0 - weight) * raw, atol=1e-9)
    if weight == 0.0:
        np.testing.assert_allclose(applied, torque)


def test_posture_torque_leaves_the_tool_and_lowers_the_posture_error() -> None:
    """The posture's torque gives the tool point no acceleration, and the joint acceleration it
    makes closes the posture error (``(q - q_p)^T A^-1 Gamma < 0``). Catches its sign, and A missing."""
    inertia, jacobian, null_space_t = position_task(Q)
    posture = Q + np.array((0.0, 0.0, 0.0, 0.4, -0.3, 0.5))
    torque = posture_torque(null_space_t, inertia, Q, posture, 100.0)
    np.testing.assert_allclose(jacobian @ np.linalg.solve(inertia, torque), 0.0, atol=1e-9)
    assert (Q - posture) @ np.linalg.solve(inertia, torque) < 0.0


def test_the_weights_ramp_between_the_policys_distances() -> None:
    """Whole below 20 mm, absorbed from 40 mm, continuous between (smoothstep)."""
    policy = DEFAULT_ABSORPTION
    full, absorbed = policy.link_full_below_m, policy.link_absorbed_from_m
    assert absorbed_weight(0.01, full, absorbed) == 0.0
    assert absorbed_weight(0.05, full, absorbed) == 1.0
    assert absorbed_weight(0.03, full, absorbed) == pytest.approx(0.5)


def test_joint_limit_potential_goes_through_the_null_space_until_a_joint_is_close() -> None:
    """NullSpaceTerms on an evaluation: the joint-limit potential at 0.12 rad from a limit reaches
    the tool with none of its part that moves the tool, at 0.03 rad whole (safety first); with no
    null space (trace N^T < 0.5) nothing changes. Catches the limits left out of the null space,
    the danger threshold ignored, and a full task's potentials projected away."""
    evaluation = ParameterLevel(ROBOT).evaluate(Q, np.zeros(len(Q)))
    inertia, jacobian, null_space_t = position_task(Q)
    terms = NullSpaceTerms(100.0, DEFAULT_ABSORPTION)
    zero = np.zeros(len(Q))
    field = LinkField(zero, zero)
    limit_torque = np.random.default_rng(5).normal(0.0, 5.0, len(Q))
    evaluation = type(evaluation)(evaluation.values, limit_torque)
    far = limit_torque + terms.correction(null_space_t, evaluation, 0.12, field, zero, None)
    np.testing.assert_allclose(jacobian @ np.linalg.solve(inertia, far), 0.0, atol=1e-9)
    near = limit_torque + terms.correction(null_space_t, evaluation, 0.03, field, zero, None)
    np.testing.assert_allclose(near, limit_torque, atol=1e-12)
    assert terms.dimension == pytest.approx(3.0)
    assert not terms.correction(np.zeros((6, 6)), evaluation, 0.12, field, zero, None).any()
