"""Admittance control on compliant moment axes in contact.

On a moment axis under force control the seed's force loop (eq. 17-18) would
leave a contact's aligning moment (0.02 N m for a round tip on a slope) to
fight the wrist joints' Coulomb friction (about 1 N m): the tool would never
turn. Instead, once the tool is in contact (:func:`cosmos.osc.contact.contact_latched`),
those axes ``Omega_a`` run admittance control: the moment error sets a rotation
speed, bounded, which a unit-mass velocity servo tracks and toward which the
joints' friction is compensated (:mod:`cosmos.osc.friction`)::

    M_f   <- M_f + beta_m (F_s - M_f)                       (sensed wrench, low-passed)
    w_a    = nu K_a Omega_a (F_d - M_f),  nu = min(1, W_max / |w_a|)   (as eq. 21's nu)
    F*_m  <- (I - Omega_a) F*_m + k_va (w_a - Omega_a xd)

and the motion command keeps no position goal on those axes: the pose error,
``xd_d`` and ``xdd_d`` lose their ``Omega_a`` part (:func:`without_axes`).

The compiled kernels of :mod:`cosmos.runtime.kernels.contact` run the same
arithmetic; these are their readable reference.
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray


def low_pass(previous: FloatArray, sample: FloatArray, blend: float) -> FloatArray:
    """One tick of a first-order low-pass: ``previous + blend (sample - previous)``.

    Args:
        previous: The filter's output at the previous tick. # (k,)
        sample: This tick's input. # (k,)
        blend: ``dt / tau``, in [0, 1].

    Returns:
        The filter's output at this tick. # (k,)
    """
    return np.asarray(previous) + blend * (np.asarray(sample) - np.asarray(previous))


def without_axes(omega_axes: FloatArray, vector: FloatArray) -> FloatArray:
    """``(I - Omega_a) v``: ``vector`` with its part along the selected axes removed. # (6,)."""
    return np.asarray(vector) - np.asarray(omega_axes).dot(vector)


def admittance_speed(
    omega_admittance: FloatArray,
    moment_setpoint: FloatArray,
    moment_filtered: FloatArray,
    gain: float,
    max_speed_rad_s: float,
) -> FloatArray:
    """The rotation speed the admittance law commands, bounded as eq. 21 bounds a speed.

    Args:
        omega_admittance: Omega_a, the moment axes under admittance control, world. # (6, 6)
        moment_setpoint: F_d, the (ramped) wrench setpoint, world, [N, N m]. # (6,)
        moment_filtered: M_f, the low-passed sensed wrench, world, [N, N m]. # (6,)
        gain: K_a, in [rad/(s N m)].
        max_speed_rad_s: W_max, in [rad/s].

    Returns:
        ``w_a``, a twist with only angular parts on the admittance axes, world. # (6,)
    """
    speed = gain * np.asarray(omega_admittance).dot(np.asarray(moment_setpoint) - np.asarray(moment_filtered))
    norm = float(np.linalg.norm(speed[3:]))
    return speed * (max_speed_rad_s / norm) if norm > max_speed_rad_s else speed


def admittance_command(
    omega_admittance: FloatArray, motion: FloatArray, speed: FloatArray, velocity: FloatArray, kv: float
) -> FloatArray:
    """F*_m with its admittance axes replaced by a unit-mass velocity servo toward ``speed``.

    Args:
        omega_admittance: Omega_a, the moment axes under admittance control, world. # (6, 6)
        motion: F*_m, the unit-mass motion command, world. # (6,)
        speed: w_a from :func:`admittance_speed`, world. # (6,)
        velocity: xd, the tool's twist, world, [m/s, rad/s]. # (6,)
        kv: k_va, the velocity servo's gain, in [1/s].

    Returns:
        ``(I - Omega_a) F*_m + k_va (w_a - Omega_a xd)``. # (6,)
    """
    omega = np.asarray(omega_admittance)
    return without_axes(omega, motion) + kv * (np.asarray(speed) - omega.dot(velocity))
