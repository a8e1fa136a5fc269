"""Admittance control on compliant moment axes (kernels.servo.servo_tick), against its analytic law.

With a unit arm (J = I, A = I, so Lambda = I and eq. 29 is ``Gamma = F``), no
friction, no gravity and the tool at rest, one tick's torque is the operational
command itself: on an admittance axis ``kv_a * K_a * (M_d - M_s)`` (bounded in
speed), on the other axes the plain unit-mass servo ``-kp e``.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.force import selection
from cosmos.runtime.kernels import servo as sk
from cosmos.runtime.kernels.parameter import fold_servo

K_A, MAX_SPEED, KV_A, KP, KV = 30.0, 0.3, 40.0, 400.0, 40.0
CONTACT_N = 1.0


def _tick(
    moment_error: np.ndarray, pose_error: np.ndarray, push_n: float, flagged: bool = True
) -> np.ndarray:
    """Torque of one tick: RX RY compliant (admittance), everything else motion, Z pushed."""
    eye, zero = np.eye(6), np.zeros(6)
    plan = selection((True, True, True, False, False, True), np.eye(3))
    servo = selection((True,) * 6, np.eye(3))
    stacked = np.zeros((6, 25))
    matrices = np.zeros((sk.MATRICES, 6, 6))
    jbar_lookahead, null_space_t = np.zeros((6, 6)), np.zeros((6, 6))
    fold_servo(
        eye, eye, eye, eye, zero, zero, zero, zero, servo.omega, servo.omega_bar,
        0.0, 0.0, zero, 0.02, 2000.0, 1.0, 0.5,
        stacked, matrices[sk.FORCE_TO_ACCELERATION], jbar_lookahead,
        matrices[sk.SINGULAR_PROJECTION], eye, null_space_t,
    )  # fmt: skip
    matrices[sk.OMEGA_BAR] = servo.omega_bar
    matrices[sk.OMEGA_ADMITTANCE] = plan.omega_bar - servo.omega_bar
    matrices[sk.ROTATION_SENSOR, :3, :3] = np.eye(3)
    scalars = np.zeros(sk.SCALARS)
    scalars[sk.MODE] = sk.MODE_HOLD
    scalars[sk.UNIFORM] = 1.0
    scalars[sk.ADMITTANCE] = float(flagged)
    scalars[sk.ADMITTANCE_GAIN] = K_A
    scalars[sk.ADMITTANCE_MAX_SPEED] = MAX_SPEED
    scalars[sk.ADMITTANCE_KV] = KV_A
    scalars[sk.MOMENT_BLEND] = 1.0  # no filtering: this tick's moment
    scalars[sk.LOOKAHEAD_S] = 0.02
    scalars[sk.CONTACT_THRESHOLD_N] = CONTACT_N
    scalars[sk.RAMP_S] = 1.0
    scalars[sk.START_S] = -10.0  # the setpoint ramp is over
    vectors = np.zeros((sk.VECTORS, 6))
    vectors[sk.KP], vectors[sk.KV] = np.full(6, KP), np.full(6, KV)
    vectors[sk.REFERENCE_ERROR] = pose_error
    vectors[sk.TORQUE_MAX] = 1e9
    sensed = np.concatenate(((0.0, 0.0, push_n), -moment_error[3:]))  # M_d = 0: error = -M_s
    state = np.zeros((sk.STATE_ROWS, 6))
    sk.servo_tick(0.0, zero, zero, sensed, scalars, vectors, matrices, eye, jbar_lookahead, stacked, state)
    return state[sk.TORQUE].copy()


def test_admittance_axes_command_kv_times_the_speed_the_moment_error_sets() -> None:
    """Catches a wrong sign (turning into the moment), a missing gain, or an axis left on position."""
    moment_error = np.array((0.0, 0.0, 0.0, 0.004, -0.002, 0.0))
    pose_error = np.array((0.001, -0.002, 0.003, 0.05, -0.04, 0.02))
    torque = _tick(moment_error, pose_error, push_n=5.0)
    expected = -KP * pose_error
    expected[3:5] = KV_A * K_A * moment_error[3:5]  # the rotation error on RX RY does not count
    assert np.allclose(torque, expected, rtol=1e-12, atol=1e-12)


def test_the_admittance_speed_is_bounded() -> None:
    """Catches an unbounded speed: a large moment error turns the tool at MAX_SPEED, along it."""
    moment_error = np.array((0.0, 0.0, 0.0, 3.0, 4.0, 0.0))
    torque = _tick(moment_error, np.zeros(6), push_n=5.0)
    assert np.allclose(torque[3:5], KV_A * MAX_SPEED * np.array((0.6, 0.8)), rtol=1e-12)


@pytest.mark.parametrize("push_n", [0.0, 0.5 * CONTACT_N])
def test_free_space_holds_the_orientation_until_a_contact_force_is_felt(push_n: float) -> None:
    """Catches a wrist that wanders in free space: below the contact force, RX RY hold position."""
    moment_error = np.array((0.0, 0.0, 0.0, 0.004, -0.002, 0.0))
    pose_error = np.array((0.0, 0.0, 0.0, 0.05, -0.04, 0.02))
    torque = _tick(moment_error, pose_error, push_n=push_n)
    assert np.allclose(torque, -KP * pose_error, rtol=1e-12, atol=1e-12)
