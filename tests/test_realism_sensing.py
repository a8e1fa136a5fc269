"""The realistic plant's sensing: quantised encoders, the velocity observer, the wrist sensor's filter.

Compared with MuJoCo's own state (``qpos``, ``qvel``, ``sensordata``), the published
drive table, and bounds derived from the encoder resolution and the observer's bandwidth
(:mod:`cosmos.realism.encoders`), not with the code's own output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.plant import Plant, SensorNoise
from cosmos.realism import PlantRealism
from cosmos.realism.arm_error import asymmetry_torque
from cosmos.realism.encoders import delay_bound, observer_step, quantisation_bound, quantised
from cosmos.realism.kernel import (
    ASYMMETRY,
    ASYMMETRY_SPEED,
    DT,
    OMEGA,
    Q_HAT,
    RESOLUTION,
    SCALARS,
    SENSED_Q,
    V_HAT,
    WRENCH_GAIN,
    sense_step,
)
from cosmos.robots import PUMA560

GEAR_RATIOS = (-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686)
"""G of the published drive table (shared/reference/puma560.md)."""
COUNTS_PER_MOTOR_REV = (1000, 800, 1000, 1000, 1000, 500)


def realistic_plant(seed: int = 1) -> Plant:
    return Plant(sensor_noise=SensorNoise(seed), realism=PlantRealism.drawn(seed, PUMA560))


def drive(plant: Plant, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Swing every joint with sinusoidal torques about gravity; per step the sensed and true q, qd."""
    sensed_q, true_q, sensed_qd, true_qd = [], [], [], []
    amplitude = np.array([40.0, 20.0, 8.0, 1.0, 1.0, 0.6])  # joint 1: over its 26 N m friction
    plant.advance()
    hold = plant.data.qfrc_bias.copy()  # gravity at home
    for k in range(steps):
        t = k * plant.dt_s
        plant.data.ctrl[:] = hold + amplitude * np.sin(
            2 * np.pi * np.array([0.7, 0.9, 1.3, 1.7, 2.1, 2.5]) * t
        )
        plant.advance()
        q, qd = plant.read_encoders()
        sensed_q.append(q)
        sensed_qd.append(qd)
        true_q.append(plant.data.qpos.copy())
        true_qd.append(plant.data.qvel.copy())
    return np.array(sensed_q), np.array(true_q), np.array(sensed_qd), np.array(true_qd)


def test_encoder_resolution_is_the_puma_s_counts_per_motor_revolution() -> None:
    """Catches a resolution in degrees or per motor turn, or a joint's count from another joint:
    one count times counts per motor revolution times |G| is a full turn."""
    realism = PlantRealism.drawn(0, PUMA560)
    turn = np.array(realism.encoder_resolution_rad) * np.array(COUNTS_PER_MOTOR_REV) * np.abs(GEAR_RATIOS)
    np.testing.assert_allclose(turn, 2 * math.pi, rtol=5e-5)


def test_encoder_readings_are_whole_counts_within_half_a_count_of_mujoco_s_angle() -> None:
    """Catches unquantised encoders (qpos handed through), truncation instead of rounding (an error
    up to a whole count, biased), and quantising with another joint's resolution."""
    plant = realistic_plant()
    sensed, true, _, _ = drive(plant, 400)
    resolution = np.array(plant.realism.encoder_resolution_rad)
    counts = sensed / resolution
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-6)
    assert np.all(np.abs(sensed - true) <= resolution / 2 + 1e-12)
    assert np.all(np.abs(sensed - true).max(axis=0) > 0.3 * resolution)  # quantised, visibly


def test_velocity_estimate_is_within_the_resolution_and_delay_bound_of_mujoco_s_qvel() -> None:
    """Catches an estimator that is unstable, lags more than its bandwidth says, or amplifies the
    quantisation (a plain difference reaches resolution/dt = 0.07-0.16 rad/s): the bound is
    omega delta / e + 2 max|qdd| / omega (cosmos.realism.encoders) from MuJoCo's own qvel."""
    plant = realistic_plant()
    _, _, estimate, qvel = drive(plant, 2500)
    omega = 2 * math.pi * plant.realism.observer_hz
    resolution = np.array(plant.realism.encoder_resolution_rad)
    qdd = np.abs(np.diff(qvel, axis=0, prepend=0.0)) / plant.dt_s
    # The delay error at a sample depends on the accelerations before it, weighted by the
    # observer's impulse response (1 + omega t) e^{-omega t}: over 12 / omega it is < 1e-4 of
    # the rest, so the largest |qdd| in that window bounds it (the window's start: skipped).
    window = int(math.ceil(12 / omega / plant.dt_s))
    recent = np.lib.stride_tricks.sliding_window_view(qdd, window, axis=0).max(axis=-1)  # (n - w + 1, 6)
    error = np.abs(estimate - qvel)[window - 1 :]
    bound = quantisation_bound(omega, resolution) + delay_bound(omega, recent)
    worst = (error / bound).max(axis=0)
    # The bound is the continuous observer's; the stepped one (omega dt = 0.25) passes the
    # rounding with a 6.5 % larger L1 norm (cosmos.realism.encoders), hence 1.1.
    assert np.all(worst <= 1.1), worst
    assert np.all(worst > 0.1)  # the bound is not vacuous: the error comes near it
    assert np.all(np.abs(qvel).max(axis=0) > 5 * quantisation_bound(omega, resolution))  # the arm moved


def test_the_controller_s_live_velocities_are_not_mujoco_s_qvel() -> None:
    """Catches the servo loop reading qvel through the live buffers on the realistic plant, and
    the ideal plant (--ideal) not reading MuJoCo's own buffers."""
    realistic, ideal = realistic_plant(), Plant()
    live = realistic.live_signals()
    data = realistic.data
    for buffer in (data.qpos, data.qvel, data.sensordata):
        for signal in (live.positions, live.velocities, live.wrench_raw):
            assert not np.shares_memory(signal, buffer)
    plain = ideal.live_signals()
    assert np.shares_memory(plain.positions, ideal.data.qpos)
    assert np.shares_memory(plain.velocities, ideal.data.qvel)
    assert np.shares_memory(plain.wrench_raw, ideal.data.sensordata)


def test_wrist_sensor_filter_follows_a_step_as_a_first_order_low_pass() -> None:
    """Catches a filter of the wrong cut-off (or none: the reading jumps), or one that does not
    settle on the true value: after a step the reading is 1 - exp(-2 pi f_c t) of it."""
    cutoff_hz, dt = 200.0, 0.001
    n = 3
    sensordata = np.zeros(8)
    index = np.arange(1, 7)
    joint_constants = np.zeros((2, n))
    scalars = np.zeros(SCALARS)
    scalars[OMEGA], scalars[DT], scalars[ASYMMETRY_SPEED] = 100.0, dt, 0.005
    scalars[WRENCH_GAIN] = 1.0 - math.exp(-2 * math.pi * cutoff_hz * dt)
    state, filtered, applied = np.zeros((3, n)), np.zeros(6), np.zeros(n)
    step = np.array([10.0, -5.0, 2.0, 0.1, -0.2, 0.3])
    sensordata[1:7] = step
    for k in range(1, 8):
        sense_step(
            np.zeros(n), np.zeros(n), sensordata, index, joint_constants, scalars, state, filtered, applied
        )
        np.testing.assert_allclose(
            filtered, step * (1 - math.exp(-2 * math.pi * cutoff_hz * k * dt)), rtol=1e-12
        )


def test_sensing_kernel_matches_its_references() -> None:
    """Catches the compiled sensing step drifting from the readable references (quantised,
    observer_step, asymmetry_torque) on random states."""
    rng = np.random.default_rng(4)
    n = 6
    resolution = np.array([1e-4, 7e-5, 0.0, 8e-5, 9e-5, 1.6e-4])
    asymmetry = rng.normal(0, 2, n)
    omega, dt = 2 * math.pi * 40, 0.001
    scalars = np.zeros(SCALARS)
    scalars[OMEGA], scalars[DT], scalars[WRENCH_GAIN], scalars[ASYMMETRY_SPEED] = omega, dt, 0.3, 0.005
    constants = np.zeros((2, n))
    constants[RESOLUTION], constants[ASYMMETRY] = resolution, asymmetry
    state, filtered, applied = np.zeros((3, n)), np.zeros(6), np.zeros(n)
    q_hat, v_hat = np.zeros(n), np.zeros(n)
    for _ in range(50):
        qpos, qvel, sensordata = rng.normal(0, 1, n), rng.normal(0, 0.01, n), rng.normal(0, 5, 9)
        index = np.array([3, 4, 5, 0, 1, 2])
        expected_filtered = filtered + 0.3 * (sensordata[index] - filtered)
        sense_step(qpos, qvel, sensordata, index, constants, scalars, state, filtered, applied)
        reading = quantised(qpos, resolution)
        q_hat, v_hat = observer_step(q_hat, v_hat, reading, omega, dt)
        np.testing.assert_allclose(state[SENSED_Q], reading, rtol=0, atol=1e-15)
        np.testing.assert_allclose(state[Q_HAT], q_hat, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(state[V_HAT], v_hat, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(applied, asymmetry_torque(qvel, asymmetry), rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(filtered, expected_filtered, rtol=1e-12)


@pytest.mark.parametrize("seed", [0, 7])
def test_realistic_sensor_at_rest_reads_the_true_wrench_plus_the_drawn_bias(seed: int) -> None:
    """Catches a filter that starts from zero (a 200 Hz transient read as a touch), and a bias
    that is not the drawn one or not added."""
    realism = PlantRealism.drawn(seed, PUMA560)
    plant = Plant(realism=realism)
    reference = Plant(edit_spec=realism.arm.apply_to_spec)  # the same arm, read exactly
    np.testing.assert_allclose(
        plant.read_wrench_sensor(), reference.read_wrench_sensor() + np.array(realism.wrist_bias), atol=1e-12
    )
    assert np.linalg.norm(realism.wrist_bias[:3]) > 1e-4


def test_one_count_speed_is_the_observers_l1_norm_stepped() -> None:
    """The stepped observer's answer to half a count: the continuous bound ``omega delta / e`` as
    the step shrinks, 6.5 % above it at ``omega dt = 0.25`` (98.5 against 92.5, encoders.py).

    Catches a dead band for the friction compensation (cosmos.osc.friction) taken from the
    wrong norm (a whole count, or the continuous bound's 6.5 % short at 1 kHz), which let one
    count's rounding through as motion."""
    from cosmos.realism.encoders import one_count_speed_rad_s, quantisation_bound

    omega, resolution = 2.0 * math.pi * 40.0, np.array((1.0e-4, 1.64e-4))
    fine = one_count_speed_rad_s(omega, 1e-6, resolution)
    np.testing.assert_allclose(fine, quantisation_bound(omega, resolution), rtol=2e-3)
    stepped = one_count_speed_rad_s(omega, 0.25 / omega, resolution)
    np.testing.assert_allclose(stepped / quantisation_bound(omega, resolution), 98.5 / 92.5, rtol=2e-3)
