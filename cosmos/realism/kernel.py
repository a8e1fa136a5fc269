"""The realistic plant's per-step sensing, compiled (numba): encoders, velocity observer, wrist filter.

One call after each physics step (:meth:`cosmos.plant.Plant.advance`) does what the
readable references do, and ``tests/test_realism_sensing.py`` compares them:

* the encoders: :func:`cosmos.realism.encoders.quantised`;
* the velocity observer: :func:`cosmos.realism.encoders.observer_step`;
* the wrist sensor's low-pass: :func:`cosmos.realism.wrist_sensor.low_pass_gain`;
* the friction the symmetric ``frictionloss`` leaves out, for the next step:
  :func:`cosmos.realism.arm_error.asymmetry_torque`.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray

OMEGA, DT, WRENCH_GAIN, ASYMMETRY_SPEED = range(4)
"""Rows of the ``scalars`` argument."""
SCALARS = 4


@kernel
def sense_step(
    qpos: FloatArray,
    qvel: FloatArray,
    wrench_true: FloatArray,
    resolution: FloatArray,
    asymmetry: FloatArray,
    scalars: FloatArray,
    sensed_q: FloatArray,
    estimate: FloatArray,
    wrench_filtered: FloatArray,
    qfrc_applied: FloatArray,
) -> None:
    """Read the encoders, update the observer and the sensor's filter, set the asymmetric friction.

    Args:
        qpos: MuJoCo's joint angles [rad]. # (n,)
        qvel: MuJoCo's joint velocities [rad/s] (the friction only; never sensed). # (n,)
        wrench_true: The wrist sensor's exact wrench [N, N m]. # (6,)
        resolution: One encoder count [rad], 0: not quantised. # (n,)
        asymmetry: ``(Tc+ - |Tc-|) / 2`` per joint [N m]. # (n,)
        scalars: OMEGA [rad/s], DT [s], WRENCH_GAIN, ASYMMETRY_SPEED [rad/s]. # (SCALARS,)
        sensed_q: The encoder readings, written [rad]. # (n,)
        estimate: Rows: the observer's angles, its velocities [rad, rad/s]. # (2, n)
        wrench_filtered: The sensor's filtered wrench, updated [N, N m]. # (6,)
        qfrc_applied: MuJoCo's applied joint forces, written [N m]. # (n,)
    """
    omega, dt = scalars[OMEGA], scalars[DT]
    position_gain, velocity_gain = 2.0 * omega * dt, omega * omega * dt
    for i in range(qpos.shape[0]):
        step = resolution[i]
        reading = math.floor(qpos[i] / step + 0.5) * step if step > 0.0 else qpos[i]
        sensed_q[i] = reading
        predicted = estimate[0, i] + dt * estimate[1, i]
        error = reading - predicted
        estimate[0, i] = predicted + position_gain * error
        estimate[1, i] += velocity_gain * error
        ramp = min(abs(qvel[i]) / scalars[ASYMMETRY_SPEED], 1.0)
        qfrc_applied[i] = -asymmetry[i] * ramp
    gain = scalars[WRENCH_GAIN]
    for k in range(6):
        wrench_filtered[k] += gain * (wrench_true[k] - wrench_filtered[k])
