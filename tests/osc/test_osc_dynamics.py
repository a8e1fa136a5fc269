"""Operational-space dynamics (eq. 13, 26-28, 34) against Pinocchio's ABA and brute force."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.dynamics import (
    SingularityPolicy,
    blend_weights,
    null_space_damping,
    operational_dynamics,
)

# The eq. 27 identities hold for any non-singular configuration; random ones can come close to a
# singularity, so these checks raise the section-5 cap out of the way.
EXACT = SingularityPolicy(max_effective_mass_kg=1e15)


def dynamics_of(state, rows=slice(None), **kwargs):
    kwargs.setdefault("policy", EXACT)
    return operational_dynamics(
        state.inertia,
        state.jacobian[rows],
        state.bias,
        state.gravity,
        state.jdot_qdot[rows],
        **kwargs,
    )


def random_spd(rng, n):
    x = rng.normal(size=(n, n))
    return x @ x.T + n * np.eye(n)


def test_eq13_and_eq27_agree_and_kinetic_energy_is_invariant(arm, rng):
    for _ in range(20):
        s = arm.random_state(rng)
        dyn = dynamics_of(s)
        assert dyn.eigenvectors.shape == (6, 0), "well-conditioned: fast path, no eigendecomposition"
        j_inv = np.linalg.inv(s.jacobian)
        lam13 = j_inv.T @ s.inertia @ j_inv  # eq. 13, square J
        np.testing.assert_allclose(dyn.lambda_, lam13, rtol=1e-8, atol=1e-8 * np.abs(lam13).max())
        xd = s.jacobian @ s.qd
        assert 0.5 * xd @ dyn.lambda_ @ xd == pytest.approx(0.5 * s.qd @ s.inertia @ s.qd, rel=1e-9)
        # p is the operational gravity force J^-T g (eq. 13) for a square J.
        np.testing.assert_allclose(dyn.p, np.linalg.solve(s.jacobian.T, s.gravity), rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(dyn.null_space_t, 0.0, atol=1e-8)


@pytest.mark.parametrize("rows", [slice(None), slice(0, 3), slice(3, 6), [0, 2, 4]])
def test_end_effector_equation_of_motion_through_aba(arm, rng, rows):
    # Eq. 26: with Gamma = J^T F + N^T Gamma_0, Pinocchio's forward dynamics gives
    # xdd = J qdd + h satisfying Lambda xdd + mu + p = F, whatever Gamma_0.
    for _ in range(10):
        s = arm.random_state(rng)
        dyn = dynamics_of(s, rows)
        j = s.jacobian[rows]
        wrench = rng.normal(scale=20.0, size=j.shape[0])
        tau = j.T @ wrench + dyn.null_space_t @ rng.normal(scale=20.0, size=arm.n)
        qdd = arm.joint_acceleration(s.q, s.qd, tau)
        xdd = j @ qdd + s.jdot_qdot[rows]
        np.testing.assert_allclose(dyn.lambda_ @ xdd + dyn.mu + dyn.p, wrench, atol=1e-7)


def test_jbar_is_the_kinetic_energy_minimising_generalised_inverse(arm, rng):
    for _ in range(10):
        s = arm.random_state(rng)
        j = s.jacobian[:3]
        dyn = dynamics_of(s, slice(0, 3))
        np.testing.assert_allclose(j @ dyn.jbar, np.eye(3), atol=1e-10)
        xd = rng.normal(size=3)
        # Brute force: minimise qd^T A qd subject to J qd = xd, by the KKT system.
        kkt = np.block([[s.inertia, j.T], [j, np.zeros((3, 3))]])
        qd_best = np.linalg.solve(kkt, np.concatenate([np.zeros(arm.n), xd]))[: arm.n]
        np.testing.assert_allclose(dyn.jbar @ xd, qd_best, atol=1e-10)
        # ... and any other solution has more kinetic energy.
        other = qd_best + dyn.null_space_t.T @ rng.normal(size=arm.n)
        np.testing.assert_allclose(j @ other, xd, atol=1e-10)
        assert other @ s.inertia @ other >= qd_best @ s.inertia @ qd_best


def test_null_space_torques_produce_no_operational_acceleration(arm, rng):
    s = arm.random_state(rng)
    dyn = dynamics_of(s, slice(0, 4))
    a_inv = np.linalg.inv(s.inertia)
    gamma = rng.normal(size=(arm.n, 20))
    np.testing.assert_allclose(s.jacobian[:4] @ a_inv @ dyn.null_space_t @ gamma, 0.0, atol=1e-10)
    # N^T is a projector.
    np.testing.assert_allclose(dyn.null_space_t @ dyn.null_space_t, dyn.null_space_t, atol=1e-10)


def test_inertia_inverse_shortcut_gives_the_same_model(arm, rng):
    s = arm.random_state(rng)
    a = dynamics_of(s, slice(0, 3))
    b = dynamics_of(s, slice(0, 3), inertia_inv=np.linalg.inv(s.inertia))
    for x, y in zip(a, b, strict=True):
        np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12)


def singular_case(rng, n=6, m=6, rank=5):
    """A random SPD A and a J of the given rank, built from an SVD so the singular direction is known."""
    a = random_spd(rng, n)
    u, _ = np.linalg.qr(rng.normal(size=(m, m)))
    v, _ = np.linalg.qr(rng.normal(size=(n, n)))
    sv = np.zeros(m)
    sv[:rank] = rng.uniform(0.5, 2.0, rank)
    j = (u * sv) @ v[:, :m].T
    return a, j, u[:, rank:]


def test_rank_deficient_jacobian_keeps_exact_lambda_off_the_singular_direction(rng):
    policy = SingularityPolicy(length_scale_m=1.0)  # no scaling: directions are plain operational ones
    for _ in range(10):
        a, j, null_dirs = singular_case(rng)
        n = a.shape[0]
        b, g, h = rng.normal(size=n), rng.normal(size=n), rng.normal(size=6)
        dyn = operational_dynamics(a, j, b, g, h, policy=policy)
        assert np.all(np.isfinite(dyn.lambda_))
        assert dyn.singular.sum() == 1
        singular = dyn.singular_directions[:, 0]
        assert abs(singular @ null_dirs[:, 0]) == pytest.approx(1.0, abs=1e-9)
        np.testing.assert_allclose(dyn.lambda_ @ singular, 0.0, atol=1e-9)
        # Independent reference: the task restricted to the orthogonal subspace (seed section 5),
        # a 5-row Jacobian J_r = P^T J with Lambda_r = (J_r A^-1 J_r^T)^-1 by plain inversion.
        basis = np.linalg.svd(j)[0][:, :5]
        j_r = basis.T @ j
        lam_r = np.linalg.inv(j_r @ np.linalg.solve(a, j_r.T))
        np.testing.assert_allclose(basis.T @ dyn.lambda_ @ basis, lam_r, rtol=1e-9)
        # Null-space torques do not accelerate the controlled subspace.
        accel = basis.T @ j @ np.linalg.solve(a, dyn.null_space_t)
        np.testing.assert_allclose(accel, 0.0, atol=1e-9)


def test_lambda_stays_bounded_and_continuous_through_a_singularity(rng):
    policy = SingularityPolicy(max_effective_mass_kg=100.0, blend_width=1.0, length_scale_m=1.0)
    a, j, null_dirs = singular_case(rng)
    # Approach the singularity along a one-parameter family: the null direction's singular value -> 0.
    u = null_dirs[:, 0]
    bump = np.outer(u, rng.normal(size=6))
    previous = None
    largest = 0.0
    for eps in np.linspace(0.2, 0.0, 401):
        dyn = operational_dynamics(a, j + eps * bump, np.zeros(6), np.zeros(6), np.zeros(6), policy=policy)
        top = np.linalg.eigvalsh(dyn.lambda_)[-1]
        largest = max(largest, top)
        if previous is not None:
            assert np.abs(dyn.lambda_ - previous).max() < 2.0  # no jump between neighbouring steps
        previous = dyn.lambda_
    assert largest <= 100.0 * (1 + 1e-9), "the effective mass never exceeds the cap"


def test_blend_weights_are_a_c1_smoothstep():
    policy = SingularityPolicy(max_effective_mass_kg=10.0, blend_width=1.0)
    s = np.linspace(0.0, 0.3, 3001)
    w = blend_weights(s, policy)
    assert w[s <= 0.1].max() == 0.0 and w[s >= 0.2].min() == 1.0
    assert np.all(np.diff(w) >= 0.0)
    slope = np.diff(w) / np.diff(s)
    assert np.abs(np.diff(slope)).max() < 0.2  # no jump in the derivative


def test_fast_and_eigen_paths_agree_where_both_apply(arm, rng):
    s = arm.random_state(rng)
    near_singular = dynamics_of(s, policy=SingularityPolicy())
    assert near_singular.singular.sum() == 1, "this sample pose is near-singular (1547 kg)"
    s = arm.random_state(rng)
    fast = dynamics_of(s)
    assert fast.eigenvectors.shape[1] == 0
    # Scaled Lambda (rotations counted as masses at L = 0.5 m): largest mass and trace.
    unscale = np.array([1, 1, 1, 2, 2, 2.0])
    masses = np.linalg.eigvalsh(fast.lambda_ * np.outer(unscale, unscale))
    # A cap between the largest mass and the trace: the trace certificate fails, so the eigen
    # path runs, yet every direction is in the exact zone.
    exact_up_to = 0.5 * (masses[-1] + masses.sum())
    policy = SingularityPolicy(max_effective_mass_kg=2 * exact_up_to, blend_width=1.0)
    slow = dynamics_of(s, policy=policy)
    assert slow.eigenvectors.shape == (6, 6) and np.all(slow.blend == 1.0)
    np.testing.assert_allclose(slow.lambda_, fast.lambda_, rtol=1e-8, atol=1e-8 * masses[-1])


def test_null_space_damping_is_eq34(arm, rng):
    s = arm.random_state(rng)
    rows = slice(0, 3)
    dyn = dynamics_of(s, rows)
    j = s.jacobian[rows]
    xi_q = 5.0
    gamma_s = null_space_damping(dyn, s.inertia, s.qd, xi_q)
    n_proj = np.eye(arm.n) - dyn.jbar @ j
    np.testing.assert_allclose(gamma_s, -xi_q * s.inertia @ n_proj @ s.qd, atol=1e-9)
    # It does not act on the end effector.
    np.testing.assert_allclose(j @ np.linalg.solve(s.inertia, gamma_s), 0.0, atol=1e-9)


def test_singular_task_projection_gives_up_rotation_not_translation():
    """A 6-DOF Jacobian with a lost direction that mixes a rotation with a translation (as the
    PUMA's wrist does: a moment about the lost axis plus a force through the wrist centre).
    Every projected command is one the arm can make (``u^T P F = 0``), its translation is
    untouched (to TRANSLATION_GIVE_UP), and the accelerations the blended Lambda produces are
    exactly P F. Catches the orthogonal removal alone (which bends the translation) and a
    projection along u itself."""
    rng = np.random.default_rng(3)
    u = np.array((0.0, -0.33, 0.0, 0.85, 0.0, 0.41))
    u /= np.linalg.norm(u)
    jacobian = rng.normal(size=(6, 6))
    jacobian -= np.outer(u, u @ jacobian)  # u^T J = 0: u is the wrench no joint feels
    inertia = random_spd(rng, 6)
    zeros = np.zeros(6)
    dyn = operational_dynamics(
        inertia, jacobian, zeros, zeros, zeros, policy=SingularityPolicy(length_scale_m=1.0)
    )
    assert dyn.blend.min() == 0.0
    p = dyn.task_projection
    for _ in range(20):
        command = rng.normal(size=6)
        projected = p @ command
        assert abs(u @ projected) < 1e-9 * np.linalg.norm(command)
        np.testing.assert_allclose(projected[:3], command[:3], atol=1e-2 * np.linalg.norm(command))
        achieved = dyn.lambda_inv @ (dyn.lambda_ @ projected)
        np.testing.assert_allclose(achieved, projected, atol=1e-6 * np.linalg.norm(command))
