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
"""Entries of the ``scalars`` argument."""
SCALARS = 4
RESOLUTION, ASYMMETRY = range(2)
"""Rows of the ``joint_constants`` argument."""
JOINT_CONSTANTS = 2
SENSED_Q, Q_HAT, V_HAT = range(3)
"""Rows of the ``joint_state`` argument."""
JOINT_STATE = 3


@kernel
def sense_step(
    qpos: FloatArray,
    qvel: FloatArray,
    sensordata: FloatArray,
    wrench_index: np.ndarray,
    joint_constants: FloatArray,
    scalars: FloatArray,
    joint_state: FloatArray,
    wrench_filtered: FloatArray,
    qfrc_applied: FloatArray,
) -> None:
    """Read the encoders, update the observer and the sensor's filter, set the asymmetric friction.

    Args:
        qpos: MuJoCo's joint angles [rad]. # (n,)
        qvel: MuJoCo's joint velocities [rad/s] (the friction only; never sensed). # (n,)
        sensordata: MuJoCo's sensor readings. # (nsensordata,)
        wrench_index: Where the wrist sensor's force then torque are in ``sensordata``;
            -1 first: no sensor. # (6,)
        joint_constants: Rows RESOLUTION (one encoder count [rad], 0: not quantised) and
            ASYMMETRY (``(Tc+ - |Tc-|) / 2`` [N m]). # (JOINT_CONSTANTS, n)
        scalars: OMEGA [rad/s], DT [s], WRENCH_GAIN, ASYMMETRY_SPEED [rad/s]. # (SCALARS,)
        joint_state: Rows SENSED_Q (the encoders' readings, written), Q_HAT and V_HAT (the
            observer's angles and velocities, updated) [rad, rad/s]. # (JOINT_STATE, n)
        wrench_filtered: The sensor's filtered wrench, updated [N, N m]. # (6,)
        qfrc_applied: MuJoCo's applied joint forces, written [N m]. # (n,)
    """
    omega, dt = scalars[OMEGA], scalars[DT]
    position_gain, velocity_gain = 2.0 * omega * dt, omega * omega * dt
    for i in range(qpos.shape[0]):
        step = joint_constants[RESOLUTION, i]
        reading = math.floor(qpos[i] / step + 0.5) * step if step > 0.0 else qpos[i]
        joint_state[SENSED_Q, i] = reading
        predicted = joint_state[Q_HAT, i] + dt * joint_state[V_HAT, i]
        error = reading - predicted
        joint_state[Q_HAT, i] = predicted + position_gain * error
        joint_state[V_HAT, i] += velocity_gain * error
        ramp = min(abs(qvel[i]) / scalars[ASYMMETRY_SPEED], 1.0)
        qfrc_applied[i] = -joint_constants[ASYMMETRY, i] * ramp
    if wrench_index[0] < 0:
        return
    gain = scalars[WRENCH_GAIN]
    for k in range(6):
        wrench_filtered[k] += gain * (sensordata[wrench_index[k]] - wrench_filtered[k])
