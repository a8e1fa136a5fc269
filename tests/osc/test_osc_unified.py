"""The unified command (eq. 16-18, 29): signs at contact, decoupling, and the servo fast path."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.dynamics import SingularityPolicy, operational_dynamics
from cosmos.osc.force import Selection, selection
from cosmos.osc.orientation import so3_exp
from cosmos.osc.unified import (
    ForceGains,
    force_command,
    force_feedback,
    integrate_force_error,
    servo_matrices,
    servo_torque,
    speed_limited_push,
    unified_torque,
)

EXACT = SingularityPolicy(max_effective_mass_kg=1e15)
GAINS = ForceGains(k_f=0.5, k_i=2.0, k_vf=10.0, integral_limit=5.0)


def model(s):
    return operational_dynamics(s.inertia, s.jacobian, s.bias, s.gravity, s.jdot_qdot, policy=EXACT)


def test_at_rest_in_contact_the_tool_applies_the_setpoint_to_the_environment(arm, rng):
    # Force control along world z (all else motion, at its goal, at rest). The environment
    # pushes back with F_ext = -F_s; with F_s = F_d Pinocchio's forward dynamics must give qdd = 0.
    s = arm.state(rng.uniform(-2, 2, arm.n), np.zeros(arm.n))
    dyn = model(s)
    sel = selection([True, True, False, True, True, True], np.eye(3))
    f_d = np.array([0.0, 0.0, -10.0, 0.0, 0.0, 0.0])  # pressing down with 10 N
    f_a = force_command(f_d, f_d, np.zeros(6), np.zeros(6), dyn.lambda_, sel.omega_bar, GAINS)
    tau = unified_torque(dyn, sel, np.zeros(6), f_a)
    wrench_on_tool_by_environment = -f_d
    qdd = arm.joint_acceleration(s.q, s.qd, tau + s.jacobian.T @ wrench_on_tool_by_environment)
    np.testing.assert_allclose(qdd, 0.0, atol=1e-8)


def test_pressing_too_lightly_pushes_harder(arm, rng):
    s = arm.state(rng.uniform(-2, 2, arm.n), np.zeros(arm.n))
    dyn = model(s)
    sel = selection([True, True, False, True, True, True], np.eye(3))
    f_d = np.array([0.0, 0.0, -10.0, 0, 0, 0])
    f_light = np.array([0.0, 0.0, -4.0, 0, 0, 0])
    f_a = force_command(f_d, f_light, np.zeros(6), np.zeros(6), dyn.lambda_, sel.omega_bar, GAINS)
    # At rest (mu = 0) with no motion command, eq. 17's F - p is Omega_bar F_a.
    f = sel.omega_bar @ f_a
    assert f[2] == pytest.approx(-10.0 - 0.5 * 6.0)


def test_free_space_acceleration_is_decoupled(arm, rng):
    # Eq. 9 with F of eq. 17-18: xdd = Omega F*_m + Lambda^-1 Omega_bar F_a, checked through ABA.
    s = arm.random_state(rng)
    dyn = model(s)
    sel = selection([True, False, True, True, True, False], so3_exp(rng.normal(size=3)))
    f_star = rng.normal(size=6)
    f_a = rng.normal(size=6)
    tau = unified_torque(dyn, sel, f_star, f_a)
    xdd = s.jacobian @ arm.joint_acceleration(s.q, s.qd, tau) + s.jdot_qdot
    expected = sel.omega @ f_star + np.linalg.solve(dyn.lambda_, sel.omega_bar @ f_a)
    np.testing.assert_allclose(xdd, expected, atol=1e-7)


def test_motion_command_on_force_axes_is_ignored(arm, rng):
    s = arm.random_state(rng)
    dyn = model(s)
    sel = selection([True, True, False, True, True, True], np.eye(3))
    f_a = rng.normal(size=6)
    base = unified_torque(dyn, sel, np.zeros(6), f_a)
    np.testing.assert_allclose(unified_torque(dyn, sel, np.eye(6)[2] * 50.0, f_a), base, atol=1e-9)


def test_servo_fast_path_equals_the_reference_and_adds_null_space_separately(arm, rng):
    s = arm.random_state(rng)
    dyn = model(s)
    sel = selection([True, False, True, True, False, True], so3_exp(rng.normal(size=3)))
    f_star, f_d, f_s, integral, xd = (rng.normal(size=6) for _ in range(5))
    f_a = force_command(f_d, f_s, integral, xd, dyn.lambda_, sel.omega_bar, GAINS)
    reference = unified_torque(dyn, sel, f_star, f_a)
    fast = servo_torque(
        servo_matrices(dyn, sel, GAINS), f_star, force_feedback(f_d, f_s, integral, GAINS), xd
    )
    np.testing.assert_allclose(fast, reference, atol=1e-9)


def test_redundant_task_compensates_gravity_in_the_null_space(arm, rng):
    # Position-only task on a 6-DoF arm: eq. 29 adds N^T (b + g); at rest with zero commands,
    # the arm does not move at all (not even its self-motion).
    s = arm.state(rng.uniform(-2, 2, arm.n), np.zeros(arm.n))
    dyn = operational_dynamics(s.inertia, s.jacobian[:3], s.bias, s.gravity, s.jdot_qdot[:3], policy=EXACT)
    sel = Selection(omega=np.eye(3), omega_bar=np.zeros((3, 3)))
    tau = unified_torque(dyn, sel, np.zeros(3), np.zeros(3), null_space_torque=np.zeros(arm.n))
    np.testing.assert_allclose(arm.joint_acceleration(s.q, s.qd, tau), 0.0, atol=1e-9)


def test_force_integral_integrates_force_axes_only_and_clamps():
    _, omega_bar = selection([True, True, False, True, True, True], np.eye(3))
    f_d = np.array([1.0, 1.0, -10.0, 1.0, 1.0, 1.0])
    f_s = np.zeros(6)
    integral = np.zeros(6)
    integral = integrate_force_error(integral, f_d, f_s, omega_bar, 0.1, limit=5.0)
    np.testing.assert_allclose(integral, [0, 0, -1.0, 0, 0, 0], atol=1e-15)
    for _ in range(100):
        integral = integrate_force_error(integral, f_d, f_s, omega_bar, 0.1, limit=5.0)
    np.testing.assert_allclose(integral, [0, 0, -5.0, 0, 0, 0], atol=1e-15)
    # Unwinds as soon as the error changes sign: the clamp stored no excess.
    integral = integrate_force_error(integral, f_d, f_d * 2, omega_bar, 0.1, limit=5.0)
    assert integral[2] == pytest.approx(-4.0)


def test_force_gains_reject_negative_values():
    with pytest.raises(ValueError, match="must be >= 0"):
        ForceGains(k_f=-1.0)


def test_a_push_at_its_speed_limit_drops_the_compliant_translations_force_loop() -> None:
    """Pushing down at its SPEED with X and Y compliant (INSERT), the tool on a chamfer that
    pushes it sideways: once the cap binds, the feedback off the push is zero and its moment
    untouched; below the cap it is eq. 18's as it was. Catches the compliant axes' force loop
    (-k_f F_s + k_i integral) left running at the cap, which carried a peg down the chamfer
    past SPEED 5 mm/s (5.65 mm/s on the ideal plant)."""
    goal = np.array([0.0, 0.0, -15.0, 0.0, 0.0, 0.0])
    sensed = np.array([2.0, -1.0, -3.0, 0.01, -0.02, 0.0])  # the chamfer's sideways push
    integral = np.array([0.1, 0.05, 0.0, 0.0, 0.0, 0.0])
    feedback = force_feedback(goal, sensed, integral, GAINS)
    inverse_mass = np.eye(6) / 10.0  # 10 kg along every axis
    moving = np.array([0.0, 0.0, -0.006, 0.0, 0.0, 0.0])  # 6 mm/s down, over a 4.5 mm/s aim
    capped, limited = speed_limited_push(feedback, goal, sensed, moving, inverse_mass, 0.0045, 300.0, 30.0)
    assert limited
    allowed = 3.0 + 10.0 * (300.0 * (0.0045 - 0.006) + 30.0 * 0.006)  # n^T F_s + m_n (...)
    np.testing.assert_allclose(capped[:3], [0.0, 0.0, -allowed], atol=1e-12)
    np.testing.assert_array_equal(capped[3:], feedback[3:])
    pressing = sensed + np.array([0.0, 0.0, -11.0, 0.0, 0.0, 0.0])  # at rest, 14 N felt
    feedback = force_feedback(goal, pressing, integral, GAINS)  # asks 15.5 N, cap 27.5 N
    uncapped, limited = speed_limited_push(
        feedback, goal, pressing, np.zeros(6), inverse_mass, 0.0045, 300.0, 30.0
    )
    assert not limited
    np.testing.assert_array_equal(uncapped, feedback)
