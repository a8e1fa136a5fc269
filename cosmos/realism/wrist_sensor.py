"""The wrist force/torque sensor as a real one reads: bandwidth, bias and noise.

A reading is ``y + b + n``: ``y`` the true wrench (MuJoCo's ``ft_force``/``ft_torque``)
through a first-order low-pass, ``b`` a constant bias, ``n`` white noise
(:class:`cosmos.plant.SensorNoise`, 0.05 N and 2 mN m standard deviation, added after the
filter as the converter's noise is).

* **Bandwidth**: a first-order low-pass at :data:`CUTOFF_HZ` (200 Hz), the order of the
  selectable output filters of small industrial F/T sensors' electronics (tens to hundreds
  of hertz); its delay ``1 / (2 pi f_c)`` is 0.8 ms. Discretised exactly for a signal held
  over the step: ``y += (1 - exp(-2 pi f_c dt)) (x - y)`` (:func:`low_pass_gain`).
* **Bias**: a real cell tares the sensor (its "bias" command) with the arm still in free
  air, averaging :data:`TARE_READINGS` readings; the offset left is that average's error,
  the noise over ``sqrt(256)``: drawn per run from the seed, normal, :data:`BIAS_FORCE_STD_N`
  per force component and :data:`BIAS_TORQUE_STD_NM` per torque component. Drift after the
  tare (temperature) is not modelled over a run's seconds; a sweep's ``bias.*`` adds an
  offset on top, to measure a program's sensitivity to it (``COMPLY RX RY`` is sensitive:
  README, "Measured").
"""

from __future__ import annotations

import math

import numpy as np

CUTOFF_HZ = 200.0
"""Cut-off of the sensor's first-order low-pass [Hz]."""

TARE_READINGS = 256
"""Readings a tare averages."""

FORCE_NOISE_STD_N, TORQUE_NOISE_STD_NM = 0.05, 0.002
"""The sensor's white noise per component (:class:`cosmos.plant.SensorNoise`'s defaults)."""

BIAS_FORCE_STD_N = FORCE_NOISE_STD_N / math.sqrt(TARE_READINGS)
"""Standard deviation of each force component's bias after the tare [N]: 3.1 mN."""

BIAS_TORQUE_STD_NM = TORQUE_NOISE_STD_NM / math.sqrt(TARE_READINGS)
"""Standard deviation of each torque component's bias after the tare [N m]: 0.125 mN m."""


def low_pass_gain(cutoff_hz: float, dt_s: float) -> float:
    """The blend ``1 - exp(-2 pi f_c dt)`` of one step of the first-order low-pass."""
    return 1.0 - math.exp(-2.0 * math.pi * cutoff_hz * dt_s)


def drawn_bias(rng: np.random.Generator) -> tuple[float, float, float, float, float, float]:
    """A bias, force then torque, sensor axes [N, N m]."""
    std = np.array([BIAS_FORCE_STD_N] * 3 + [BIAS_TORQUE_STD_NM] * 3)
    f = rng.normal(0.0, std)
    return (float(f[0]), float(f[1]), float(f[2]), float(f[3]), float(f[4]), float(f[5]))
