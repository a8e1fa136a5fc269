"""A setpoint's ``uniform_gains``, judged in floats, against NumPy's comparison of the arrays."""

from __future__ import annotations

import math

import numpy as np

from cosmos.runtime.setpoint import MotionMode, ServoSetpoint


def test_uniform_gains_is_numpys_judgement() -> None:
    """Catches the float judgement telling gains apart where NumPy does not, or the reverse (a last
    axis different, a signed zero, a NaN, the damping alone different): the servo skips its frame
    rotations only for gains ``np.all(gains == gains[0])`` calls uniform."""
    rng = np.random.default_rng(5)
    cases = [np.full(6, 400.0), np.array([400.0] * 5 + [400.0000001]), np.array([0.0, -0.0] * 3)]
    cases += [np.array([math.nan] * 6), np.array([1.0, math.nan, 1.0, 1.0, 1.0, 1.0])]
    cases += [rng.choice([100.0, 400.0], 6) for _ in range(20)]
    for kp in cases:
        for kv in (np.full(6, 40.0), np.array([40.0, 40.0, 40.0, 20.0, 40.0, 40.0])):
            setpoint = ServoSetpoint(MotionMode.HOLD, np.zeros(3), np.eye(3), kp_task=kp, kv_task=kv)
            expected = bool(np.all(kp == kp[0]) and np.all(kv == kv[0]))
            assert setpoint.uniform_gains is expected, (kp, kv)
