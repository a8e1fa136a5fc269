"""The servo tick's contact laws, compiled (numba): latches, admittance, Coulomb compensation.

Each mirrors its readable reference in :mod:`cosmos.osc`, against which
``tests/runtime/test_contact_kernel.py`` checks it on seeded random inputs and
at the edges (thresholds, bounds, clipping):

* :func:`touch_latched`: :func:`cosmos.osc.contact.touch_latched` (the force integral's latch);
* :func:`contact_latched`: :func:`cosmos.osc.contact.contact_latched` (the admittance latch);
* :func:`low_pass_into`: :func:`cosmos.osc.admittance.low_pass` (the sensed moment's filter);
* :func:`admittance_speed`: :func:`cosmos.osc.admittance.admittance_speed`;
* :func:`admittance_command`: :func:`cosmos.osc.admittance.admittance_command`;
* :func:`coulomb_compensation_into`: :func:`cosmos.osc.friction.friction_intent` and
  :func:`cosmos.osc.friction.coulomb_compensation`.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.runtime.kernels.linear import matvec, max_abs_product

FloatArray = np.ndarray


@kernel
def touch_latched(touching: bool, omega_bar: FloatArray, wrench: FloatArray, threshold_n: float) -> bool:
    """``touching or max |Omega_bar F_s| > F_contact``: something pushes back on a force axis."""
    return touching or max_abs_product(omega_bar, wrench) > threshold_n


@kernel
def contact_latched(latched: bool, wrench: FloatArray, threshold_n: float) -> bool:
    """``latched or |f_s| > F_contact``: any contact force, f_s the wrench's force part."""
    if latched:
        return True
    push = math.sqrt(wrench[0] ** 2 + wrench[1] ** 2 + wrench[2] ** 2)
    return push > threshold_n


@kernel
def low_pass_into(filtered: FloatArray, sample: FloatArray, blend: float) -> None:
    """``filtered += blend (sample - filtered)``, in place: one tick of a first-order low-pass."""
    for i in range(filtered.shape[0]):
        filtered[i] += blend * (sample[i] - filtered[i])


@kernel
def admittance_speed(
    omega_admittance: FloatArray,
    setpoint: FloatArray,
    moment_filtered: FloatArray,
    gain: float,
    max_speed_rad_s: float,
) -> FloatArray:
    """``w_a = nu K_a Omega_a (F_d - M_f)``, its angular norm bounded by ``max_speed_rad_s``. # (6,)."""
    speed = matvec(omega_admittance, setpoint - moment_filtered) * gain
    norm = math.sqrt(speed[3] ** 2 + speed[4] ** 2 + speed[5] ** 2)
    if norm > max_speed_rad_s:
        speed *= max_speed_rad_s / norm
    return speed


@kernel
def admittance_command(
    omega_admittance: FloatArray, motion: FloatArray, speed: FloatArray, velocity: FloatArray, kv: float
) -> FloatArray:
    """``(I - Omega_a) F*_m + k_va (w_a - Omega_a xd)``: F*_m with a velocity servo on Omega_a. # (6,)."""
    servo = kv * (speed - matvec(omega_admittance, velocity))
    return motion - matvec(omega_admittance, motion) + servo


@kernel
def coulomb_compensation_into(
    torque: FloatArray,
    coulomb: FloatArray,
    qd: FloatArray,
    jbar_lookahead: FloatArray,
    acceleration: FloatArray,
    coulomb_nm: FloatArray,
    intent_scale: float,
    blend: float,
) -> None:
    """One tick of the low-passed Coulomb compensation, into ``coulomb`` and added to ``torque``.

    Args:
        torque: Gamma, in [N m]; the compensation is added. # (6,)
        coulomb: Gamma_f of the previous tick in, this tick's out, in [N m]. # (6,)
        qd: Joint velocities, in [rad/s]. # (6,)
        jbar_lookahead: ``L Jbar``. # (6, 6)
        acceleration: ``a + xd_c / L``, world. # (6,)
        coulomb_nm: Gamma_c, in [N m]. # (6,)
        intent_scale: ``1 / v_c``, in [s/rad].
        blend: beta, in [0, 1].
    """
    for i in range(6):
        acc = 0.0
        for k in range(6):
            acc += jbar_lookahead[i, k] * acceleration[k]
        intent = (qd[i] + acc) * intent_scale
        target = coulomb_nm[i] * min(max(intent, -1.0), 1.0)
        coulomb[i] += blend * (target - coulomb[i])
        torque[i] += coulomb[i]
