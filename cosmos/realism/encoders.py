"""Joint encoders and the velocity the controller estimates from them (readable reference).

**Resolution.** Each arm's encoders are :attr:`cosmos.robots.Robot.encoder_counts_per_degree`.
The PUMA 560's joints are read by incremental encoders on the motor
shafts. The Unimation controller's conversion factors, encoder counts per joint degree
(173.92, 239.59, 149.18, 211.21, 199.79, 106.51 for joints 1-6; posted with the PUMA's
servo interface on comp.robotics, "Puma 560 encoders->degrees", 4 Oct 1990), are 1000,
800, 1000, 1000, 1000 and 500 counts per motor revolution through the published gear
ratios (``shared/reference/puma560.md``: 62.6111, 107.815, ...) to five digits. One count
is ``2 pi / (counts_per_rev |G|)`` at the joint: 1.00e-4, 7.28e-5, 1.17e-4, 8.26e-5,
8.74e-5 and 1.64e-4 rad. A reading is the joint angle rounded to a whole count
(:func:`quantised`): the error is within half a count. The Panda's resolution is assumed
(Franka publishes none): a 19-bit absolute encoder on each joint's link side, 1.2e-5 rad.

**Velocity.** The controller gets no joint velocity: it estimates it from the quantised
angles with a kinematic tracking observer per joint (:func:`observer_step`), a critically
damped second-order loop of bandwidth ``omega``::

    q_hat' = v_hat + 2 omega (q_m - q_hat),    v_hat' = omega^2 (q_m - q_hat)

It needs no dynamic model (the controller's model is the one that is wrong now), and
from the angle to ``v_hat`` it is ``omega^2 s / (s + omega)^2``: it rolls off above
``omega``, where a filtered difference ``s / (1 + s tau)`` passes the quantisation's
steps with gain ``1 / tau``. Simulated at joint 2's resolution: creeping at 0.005 rad/s
the observer errs 1.4e-3 rad/s rms at 30 Hz and 3.0e-3 at 50 Hz, a difference low-passed
at 50 Hz 5.7e-3 and at 100 Hz 9.3e-3; along a smooth 0.5 rad/s move the observer at 50 Hz
errs 4.4e-3 rms, the 50 Hz difference 6.3e-3. 40 Hz is between the observer's two.

Its error has two parts, each bounded by the L1 norm of an impulse response
(``tests/test_realism_sensing.py`` checks them against MuJoCo's own ``qvel``):

* quantisation: ``q_m = q + e``, ``|e| <= delta / 2``, passes with ``omega^2 s / (s +
  omega)^2``, whose impulse response ``omega^2 (1 - omega t) e^{-omega t}`` has L1 norm
  ``2 omega / e``: ``|v_hat - v| <= omega delta / e`` (:func:`quantisation_bound`);
* delay: ``v - v_hat = (s + 2 omega) / (s + omega)^2`` times the acceleration, L1 norm
  ``2 / omega``: ``|v_hat - v| <= 2 max |qdd| / omega``, the lag of a ``2 / omega`` delay
  (8 ms at the default 40 Hz) (:func:`delay_bound`).

At 40 Hz the first is 9.2e-3 rad/s at joint 1 and 1.5e-2 rad/s at joint 6. These are the
continuous observer's; stepped at 1 kHz (``omega dt = 0.25``) the rounding's L1 norm is
6.5 % larger (98.5 against 92.5 per rad of rounding at 40 Hz).
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.robots import Robot

OBSERVER_HZ = 40.0
"""Default bandwidth of the velocity observer [Hz]: delay 2 / omega = 8 ms."""


def encoder_resolution_rad(robot: Robot) -> FloatArray:
    """One encoder count per joint of ``robot`` [rad]. # (n,).

    0 (no quantisation) if it has no encoders' counts
    (:attr:`cosmos.robots.Robot.encoder_counts_per_degree`).
    """
    counts = robot.encoder_counts_per_degree
    if counts is None:
        return np.zeros(robot.dof)
    return np.radians(1.0 / np.asarray(counts, dtype=float))


def quantised(q: FloatArray, resolution_rad: FloatArray) -> FloatArray:
    """Joint angles rounded to the nearest whole count [rad]; joints of resolution 0 unchanged. # (n,)."""
    counts = np.floor(q / np.where(resolution_rad > 0, resolution_rad, 1.0) + 0.5)
    return np.where(resolution_rad > 0, counts * resolution_rad, q)


def observer_step(
    q_hat: FloatArray, v_hat: FloatArray, q_measured: FloatArray, omega: float, dt_s: float
) -> tuple[FloatArray, FloatArray]:
    """One step of the tracking observer (module docstring), semi-implicit Euler.

    Args:
        q_hat: Estimated angles [rad]. # (n,)
        v_hat: Estimated velocities [rad/s]. # (n,)
        q_measured: The encoder readings [rad]. # (n,)
        omega: Bandwidth [rad/s].
        dt_s: Sample period [s].

    Returns:
        The new ``(q_hat, v_hat)``.
    """
    predicted = q_hat + dt_s * v_hat
    error = q_measured - predicted
    return predicted + 2.0 * omega * dt_s * error, v_hat + omega * omega * dt_s * error


def quantisation_bound(omega: float, resolution_rad: FloatArray) -> FloatArray:
    """Largest velocity error from the encoders' rounding, ``omega delta / e`` [rad/s]. # (n,)."""
    return omega * resolution_rad / math.e


def one_count_speed_rad_s(omega: float, dt_s: float, resolution_rad: FloatArray) -> FloatArray:
    """The stepped observer's largest answer to the rounding, ``(delta / 2) sum |h_k|`` [rad/s]. # (n,).

    ``h`` is :func:`observer_step`'s response of ``v_hat`` to a unit impulse of the reading
    (summed until it has died away, ``60 / (omega dt)`` steps); a rounding error within half
    a count moves the estimate at most this far. It is :func:`quantisation_bound` for the
    continuous observer, 6.5 % more stepped at ``omega dt = 0.25`` (module docstring): 7.2e-3
    to 1.6e-2 rad/s on the PUMA at 40 Hz and 1 kHz. The friction compensation takes it as the
    speed below which a sensed joint speed is noise (:mod:`cosmos.osc.friction`).
    """
    q_hat, v_hat, total = 0.0, 0.0, 0.0
    for k in range(int(math.ceil(60.0 / (omega * dt_s)))):
        predicted = q_hat + dt_s * v_hat
        error = (1.0 if k == 0 else 0.0) - predicted
        q_hat, v_hat = predicted + 2.0 * omega * dt_s * error, v_hat + omega * omega * dt_s * error
        total += abs(v_hat)
    return 0.5 * np.asarray(resolution_rad, dtype=float) * total


def delay_bound(omega: float, max_acceleration: FloatArray) -> FloatArray:
    """Largest velocity error from the observer's delay, ``2 max |qdd| / omega`` [rad/s]. # (n,)."""
    return 2.0 * max_acceleration / omega
