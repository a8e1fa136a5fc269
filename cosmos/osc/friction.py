"""Coulomb friction compensation of the joints, toward the motion they are told to make.

The seed's torque (eq. 29) models no joint friction; the PUMA's joints have
Coulomb friction of the order of a newton metre, enough to stall a slow
motion or a light push. The servo adds, per joint, the friction torque in the
direction the joint is moving or, from rest, is being told to move::

    intent   = (dz(qd) + Jbar (L a + xd_c)) / v_c                (Jbar: eq. 28)
    target   = Gamma_c(sign intent) clip(intent, -1, 1)
    Gamma_f <- Gamma_f + beta (target - Gamma_f)                  (once per servo tick)

``a`` is the commanded operational acceleration and ``L`` a short look-ahead,
so that ``Jbar L a`` is the joint speed the command is about to produce;
``xd_c`` is an operational speed commanded outright (a tracked trajectory's
``xd_d`` on the motion axes, an admittance speed, a push at its speed limit),
so that a slow joint is not left to stick. ``dz(qd) = sign(qd) max(|qd| - d, 0)``
drops a dead band ``d`` per joint from the sensed speed: on a plant read by encoders,
the velocity observer's answer to one count's rounding (7e-3 to 1.6e-2 rad/s on the PUMA,
:func:`cosmos.realism.encoders.one_count_speed_rad_s`), so that the rounding alone, at
rest, does not ask for the friction torque (with ``v_c`` below that noise it asked
for all of it, and the arm dithered within one count at 1-1.8e-3 rad/s after
eq. 38 had stopped it). It applies in a hold in free space (HOLD, WAIT, POSTURE), where
the noise is all the motion there is; 0 where the speed is read exactly and in every
segment that moves or pushes, where that noise is a welcome dither (with the band, a held
10 N push rang between 6.5 and 13.3 N, and a MOVE TO's arrival changed the next slide's
push). ``v_c`` is the joint speed at which the full friction torque is compensated
(a linear ramp below it avoids chattering at rest), ``Gamma_c(+)`` and ``Gamma_c(-)`` are the joint's friction
turning positively and negatively (the PUMA's published drive table differs by up to a
factor of 2.6 between the two: compensating their mean leaves 3 N m on joint 2
unanswered), and the first-order low-pass ``beta = dt / tau`` keeps a
new setpoint or a change of sign from stepping the torque.

The compiled kernels of :mod:`cosmos.runtime.kernels.contact` run the same
arithmetic; these are their readable reference.
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray


def friction_intent(
    qd: FloatArray,
    jbar: FloatArray,
    acceleration: FloatArray,
    commanded_speed: FloatArray,
    lookahead_s: float,
    full_speed_rad_s: float,
    dead_band_rad_s: FloatArray | float = 0.0,
) -> FloatArray:
    """The joints' intended motion, scaled so that +-1 asks for the full friction torque.

    Args:
        qd: Joint velocities, in [rad/s]. # (n,)
        jbar: The dynamically consistent inverse ``Jbar = A^-1 J^T Lambda`` (eq. 28). # (n, 6)
        acceleration: The commanded operational acceleration, world, [m/s^2, rad/s^2]. # (6,)
        commanded_speed: An operational speed commanded outright, world, [m/s, rad/s]
            (zeros where none is). # (6,)
        lookahead_s: L, how far ahead the commanded acceleration counts, in [s].
        full_speed_rad_s: v_c, the joint speed at which the full torque is compensated, in [rad/s].
        dead_band_rad_s: d, the sensed speed's noise per joint, in [rad/s]. # (n,) or scalar

    Returns:
        ``(dz(qd) + Jbar (L a + xd_c)) / v_c``, unclipped. # (n,)
    """
    operational = lookahead_s * np.asarray(acceleration) + np.asarray(commanded_speed)
    qd = np.asarray(qd, dtype=float)
    beyond = np.sign(qd) * np.maximum(np.abs(qd) - np.asarray(dead_band_rad_s), 0.0)
    return (beyond + np.asarray(jbar).dot(operational)) / full_speed_rad_s


def coulomb_compensation(
    previous_nm: FloatArray,
    positive_nm: FloatArray,
    negative_nm: FloatArray,
    intent: FloatArray,
    blend: float,
) -> FloatArray:
    """One servo tick of the low-passed Coulomb compensation torque.

    Args:
        previous_nm: Gamma_f of the previous tick, in [N m]. # (n,)
        positive_nm: Gamma_c(+), each joint's Coulomb friction turning positively, in [N m]. # (n,)
        negative_nm: Gamma_c(-), the same turning negatively (a magnitude), in [N m]. # (n,)
        intent: :func:`friction_intent`. # (n,)
        blend: beta, the low-pass's share of the new target per tick, in [0, 1].

    Returns:
        ``Gamma_f + beta (Gamma_c(sign intent) clip(intent, -1, 1) - Gamma_f)``, in [N m]. # (n,)
    """
    coulomb = np.where(np.asarray(intent) > 0.0, positive_nm, negative_nm)
    target = coulomb * np.clip(intent, -1.0, 1.0)
    return np.asarray(previous_nm) + blend * (target - np.asarray(previous_nm))


COULOMB_ERROR_RANGE = 0.1
"""The most a joint's Coulomb friction is taken to differ from the model's, as a share of it [1].

Friction changes with temperature and wear more than a link's mass does; the realistic plant
draws each joint's within 10 % (docs/plant.md)."""
COULOMB_ADAPTATION_RATE_PER_S = 2.0
"""r, the rate at which a joint's Coulomb error is learnt [1/s]: a decade below the servo's own
loops (eq. 20-21's cruise integral at a double root of ``kv / 2`` = 20 /s), so that it does not
fight them, and within about 0.5 s of motion."""


def adapt_coulomb_error(
    error: FloatArray,
    reference_speed: FloatArray,
    feedback_torque: FloatArray,
    positive_nm: FloatArray,
    negative_nm: FloatArray,
    full_speed_rad_s: float,
    dt_s: float,
) -> FloatArray:
    """One servo tick of each joint's Coulomb friction error ``eps``, learnt from what the servo corrects.

    The compensation is ``(1 + eps) Gamma_c(sign intent) clip(intent, -1, 1)``
    (:func:`coulomb_compensation` with the levels scaled). The joints' friction is the model error
    that changes most along a motion: where the arm's is lower than the model's, the compensation
    pushes the tool on, where higher it holds it back, and each joint's share of it turns with the
    joint (its sign) and grows with the joint's speed within the compensation's ramp. Eq. 19 and
    eq. 20-21 with their integrals (:mod:`cosmos.osc.cruise_speed`,
    :mod:`cosmos.osc.integral_action`) answer it with an operational force, learnt again wherever it
    changes: a MOVE ... VIA's leg whose joints turn otherwise (SPEED 5 and 10 mm/s on the realistic
    plant, joint 1's friction drawn 7-10 % under the model's on seeds 0 and 2: legs started up to
    1.57 times their SPEED), a slow MOVE whose shoulder turns within the compensation's ramp (1 mm/s
    straight down: 0.97 of its SPEED, seeds 1-4). Here the error is learnt in the joints::

        eps_i <- clip(eps_i + r sigma_i tau_i / Gamma_c,i(sign sigma_i) dt, -range, range)

    with ``tau = J^T Lambda F*_fb``, the joint torques of the servo's feedback (eq. 19's
    ``-kp e - kv (xd - xd_d)``, eq. 20's ``kv (v_d - xd)``: what the model's torque left to correct),
    and ``sigma_i = clip(qd_r,i / v_c, -1, 1)`` the share of its friction the joint's reference motion
    ``qd_r = Jbar v_r`` (eq. 28; ``v_r = xd + F*_fb / kv``, eq. 21's desired velocity on a goal
    motion, ``xd_d - (kp / kv) e`` on a tracked one) asks compensated: a joint the servo pushes
    along its motion is under-compensated. ``v_r`` holds no sensed speed (the velocity terms cancel),
    so the sensed speed's noise, which ``tau`` carries, does not bias ``eps``. The error is the arm's:
    it is kept from segment to segment, scales the compensation in every segment, and is learnt only
    in free motion (no force axis, no compliant axis, no contact felt: a contact's force is not the
    joints' friction) and not in a hold (nothing moves).

    Args:
        error: eps of the previous tick, per joint. # (n,)
        reference_speed: ``qd_r = Jbar v_r``, the joints' reference motion, in [rad/s]. # (n,)
        feedback_torque: ``tau = J^T Lambda F*_fb``, in [N m]. # (n,)
        positive_nm: Gamma_c(+), in [N m]. # (n,)
        negative_nm: Gamma_c(-), in [N m]. # (n,)
        full_speed_rad_s: v_c, the joint speed at which the full torque is compensated, in [rad/s].
        dt_s: Servo period, in [s].

    Returns:
        The new eps, within +-:data:`COULOMB_ERROR_RANGE`. # (n,)
    """
    sigma = np.clip(np.asarray(reference_speed, dtype=float) / full_speed_rad_s, -1.0, 1.0)
    level = np.where(sigma > 0.0, positive_nm, negative_nm)
    safe = np.where(level > 0.0, level, 1.0)
    step = np.where(level > 0.0, COULOMB_ADAPTATION_RATE_PER_S * sigma * feedback_torque / safe * dt_s, 0.0)
    return np.clip(np.asarray(error, dtype=float) + step, -COULOMB_ERROR_RANGE, COULOMB_ERROR_RANGE)
