"""The servo tick's contact laws, compiled (numba): latches, admittance, Coulomb compensation.

Each mirrors its readable reference in :mod:`cosmos.osc`, against which
``tests/runtime/test_contact_kernel.py`` checks it on seeded random inputs and
at the edges (thresholds, bounds, clipping):

* :func:`touch_latched`: :func:`cosmos.osc.contact.touch_latched` (the force integral's latch);
* :func:`contact_latched`: :func:`cosmos.osc.contact.contact_latched` (the admittance latch);
* :func:`push_landed`, :func:`force_goal_latched`: :func:`cosmos.osc.contact.push_landed` (a held push's
  goal counts once landed);
* :func:`low_pass_into`: :func:`cosmos.osc.admittance.low_pass` (the sensed moment's filter);
* :func:`admittance_speed`: :func:`cosmos.osc.admittance.admittance_speed`;
* :func:`admittance_command`: :func:`cosmos.osc.admittance.admittance_command`;
* :func:`coulomb_compensation_into`: :func:`cosmos.osc.friction.friction_intent` and
  :func:`cosmos.osc.friction.coulomb_compensation`;
* :func:`speed_limited_push_into`: :func:`cosmos.osc.unified.speed_limited_push` (a push's SPEED);
* :func:`touch_braking_into`: :func:`cosmos.osc.contact.touch_braking` (a CONTACT's approach);
* :func:`tilt_window_into`: :func:`cosmos.osc.tilt_window.tilt_window` (an INSERT's rotations);
* :func:`insert_compliance_into`: :func:`cosmos.osc.tilt_window.insert_compliance` (the window by
  depth, and the push across the insertion toward the part's lean);
* :func:`integrated_force_error`: :func:`cosmos.osc.tilt_window.integrated_force_error` (the force
  integral's error, less its part along that push).

A held push's kernels are :mod:`cosmos.runtime.kernels.held_push`.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.contact import LANDED_PUSH, LANDED_SPEED_MPS, TOUCH_BRAKING_N_PER_KG
from cosmos.osc.unified import REACH_FRACTION
from cosmos.runtime.kernels.linear import matvec, max_abs_product

FloatArray = np.ndarray

LANDED = np.array((LANDED_SPEED_MPS, LANDED_PUSH))
"""cosmos.osc.contact.push_landed's limits: the speed [m/s], the share of the goal."""
LANDED_AFTER_RAMP = np.array((LANDED_SPEED_MPS, np.inf))
"""... once the setpoint's ramp is over: at rest along the push, whatever it pushes."""


@kernel
def touch_latched(touching: bool, omega_bar: FloatArray, wrench: FloatArray, threshold_n: float) -> bool:
    """``touching or max |Omega_bar F_s| > F_contact``: something pushes back on a force axis."""
    return touching or max_abs_product(omega_bar, wrench) > threshold_n


@kernel
def goal_reached(reached: bool, goal: FloatArray, wrench: FloatArray, fraction: float) -> bool:
    """``reached or F_goal . F_s >= fraction |F_goal|^2`` (cosmos.osc.unified.force_goal_reached)."""
    if reached:
        return True
    size = 0.0
    felt = 0.0
    for i in range(goal.shape[0]):
        size += goal[i] * goal[i]
        felt += goal[i] * wrench[i]
    return felt >= fraction * size


@kernel
def push_landed(force_goal: FloatArray, wrench: FloatArray, velocity: FloatArray, limits: FloatArray) -> bool:
    """:func:`cosmos.osc.contact.push_landed`; ``limits``: the speed [m/s], the share of the goal."""
    push = math.sqrt(force_goal[0] ** 2 + force_goal[1] ** 2 + force_goal[2] ** 2)
    if not push > 0.0:
        return True
    along = (force_goal[0] * velocity[0] + force_goal[1] * velocity[1] + force_goal[2] * velocity[2]) / push
    felt = (force_goal[0] * wrench[0] + force_goal[1] * wrench[1] + force_goal[2] * wrench[2]) / push
    return abs(along) <= limits[0] and felt <= limits[1] * push


@kernel
def force_goal_latched(
    reached: bool, goal: FloatArray, wrench: FloatArray, velocity: FloatArray, held: bool, ramped: bool
) -> bool:
    """The force integral's goal latch (:func:`goal_reached`), a held push's once landed.

    A held push's goal counts only once :func:`push_landed`, and then also once its setpoint's
    ramp is over (``ramped``), when a push over its goal counts too (at rest, it is no impact:
    a held block landed on another at 19 N and stayed at 14 N for a 4 N CONTACT, the joints'
    friction holding the arm, the integral waiting for the push to fall); a push held to its
    speed (INSERT) latches on its goal alone.
    """
    if reached:
        return True
    if not held:
        return goal_reached(False, goal, wrench, REACH_FRACTION)
    if not push_landed(goal, wrench, velocity, LANDED_AFTER_RAMP if ramped else LANDED):
        return False
    return ramped or goal_reached(False, goal, wrench, REACH_FRACTION)


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
    positive_nm: FloatArray,
    negative_nm: FloatArray,
    dead_band: FloatArray,
    moving: bool,
    intent_scale: float,
    blend: float,
) -> None:
    """One tick of the low-passed Coulomb compensation, into ``coulomb`` and added to ``torque``.

    Args:
        torque: Gamma, in [N m]; the compensation is added. # (n,)
        coulomb: Gamma_f of the previous tick in, this tick's out, in [N m]. # (n,)
        qd: Joint velocities, in [rad/s]. # (n,)
        jbar_lookahead: ``L Jbar``. # (n, 6)
        acceleration: ``a + xd_c / L``, world. # (6,)
        positive_nm: Gamma_c(+), in [N m]. # (n,)
        negative_nm: Gamma_c(-), in [N m]. # (n,)
        dead_band: d, the sensed speed's noise, dropped from ``|qd|`` in a hold, in [rad/s]. # (n,)
        moving: The segment moves the tool or pushes (a goal, a trajectory, force-controlled
            or compliant axes): the noise is kept, a dither against the stiction that would
            hold a push off its goal; False in a hold, where the noise is all the motion there is.
        intent_scale: ``1 / v_c``, in [s/rad].
        blend: beta, in [0, 1].
    """
    for i in range(torque.shape[0]):
        acc = 0.0
        for k in range(6):
            acc += jbar_lookahead[i, k] * acceleration[k]
        speed, band = qd[i], 0.0 if moving else dead_band[i]
        if speed > band:
            speed -= band
        elif speed < -band:
            speed += band
        else:
            speed = 0.0
        intent = (speed + acc) * intent_scale
        level = positive_nm[i] if intent > 0.0 else negative_nm[i]
        target = level * min(max(intent, -1.0), 1.0)
        coulomb[i] += blend * (target - coulomb[i])
        torque[i] += coulomb[i]


@kernel
def push_axis(force_goal: FloatArray, force_to_acceleration: FloatArray) -> tuple[float, float, float, float]:
    """:func:`cosmos.osc.unified.push_axis`: a push's direction ``n`` and ``n^T Lambda^-1 Omega_bar n``.

    The inverse of the tool's mass along the push; all zeros when F_d has no force.
    """
    push = math.sqrt(force_goal[0] ** 2 + force_goal[1] ** 2 + force_goal[2] ** 2)
    if not push > 0.0:
        return 0.0, 0.0, 0.0, 0.0
    n0, n1, n2 = force_goal[0] / push, force_goal[1] / push, force_goal[2] / push
    f2a = force_to_acceleration
    inverse_mass = 0.0
    for i, ni in ((0, n0), (1, n1), (2, n2)):
        inverse_mass += ni * (f2a[i, 0] * n0 + f2a[i, 1] * n1 + f2a[i, 2] * n2)
    return n0, n1, n2, inverse_mass


@kernel
def speed_limited_push_into(
    feedback: FloatArray,
    force_goal: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    force_to_acceleration: FloatArray,
    max_speed: float,
    kv: float,
    k_vf: float,
    feedforward: float,
) -> tuple[bool, float]:
    """:func:`cosmos.osc.unified.speed_limited_push`, applied to ``feedback`` in place.

    Args:
        feedback: F_fb in, capped along the push out, world, [N, N m]. # (6,)
        force_goal: F_d (not ramped), world. # (6,)
        force_sensed: F_s, world. # (6,)
        velocity: Tool twist, world. # (6,)
        force_to_acceleration: ``Lambda^-1 Omega_bar``. # (6, 6)
        max_speed: V_max, in [m/s].
        kv: Velocity gain of the speed servo, in [1/s].
        k_vf: The force axes' damping gain, in [1/s].
        feedforward: The speed reference's own acceleration, in [m/s^2].

    Returns:
        ``(limited, n^T xd)``: whether the cap bound and the speed along the push.
    """
    n0, n1, n2, inverse_mass = push_axis(force_goal, force_to_acceleration)
    if not inverse_mass > 0.0:
        return False, 0.0
    along = n0 * velocity[0] + n1 * velocity[1] + n2 * velocity[2]
    allowed = (n0 * force_sensed[0] + n1 * force_sensed[1] + n2 * force_sensed[2]) + (
        feedforward + kv * (max_speed - along) + k_vf * along
    ) / inverse_mass
    asked = n0 * feedback[0] + n1 * feedback[1] + n2 * feedback[2]
    if not asked > allowed:
        return False, along
    feedback[0] = allowed * n0  # the compliant translations' force loop dropped (the reference)
    feedback[1] = allowed * n1
    feedback[2] = allowed * n2
    return True, along


@kernel
def touch_braking_into(
    motion: FloatArray, wrench: FloatArray, velocity: FloatArray, params: FloatArray, free_speed: float
) -> None:
    """:func:`cosmos.osc.contact.touch_braking` in place; ``params``: touch_n, m_tool, k_b.

    With ``free_speed`` 0 it is :func:`cosmos.osc.held_push.touch_damping` (a COMPLY spring's touch).
    """
    touch_n, mass, gain = params[0], params[1], params[2]
    c0, c1, c2 = wrench[0] - mass * motion[0], wrench[1] - mass * motion[1], wrench[2] - mass * motion[2]
    push = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    if not push > max(touch_n, TOUCH_BRAKING_N_PER_KG * mass):
        return
    n0, n1, n2 = c0 / push, c1 / push, c2 / push
    along = n0 * velocity[0] + n1 * velocity[1] + n2 * velocity[2] - free_speed
    if along > 0.0:
        motion[0] -= gain * along * n0
        motion[1] -= gain * along * n1
        motion[2] -= gain * along * n2


@kernel
def tilt_window_into(speed: FloatArray, tilt: FloatArray, window_rad: float, rate: float) -> None:
    """:func:`cosmos.osc.tilt_window.tilt_window` on ``speed`` (``w_a``) in place."""
    t0, t1, t2 = tilt[3], tilt[4], tilt[5]
    size = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    if size > window_rad:
        back = rate * (size - window_rad) / size
        speed[3] -= back * t0
        speed[4] -= back * t1
        speed[5] -= back * t2


@kernel
def insert_compliance_into(
    speed: FloatArray,
    slide: FloatArray,
    tilt: FloatArray,
    error: FloatArray,
    velocity: FloatArray,
    force_goal: FloatArray,
    wrench: FloatArray,
    omega_bar: FloatArray,
    params: FloatArray,
) -> None:
    """:func:`cosmos.osc.tilt_window.insert_compliance` in place: ``w_a`` stopped, F_l added to ``slide``.

    ``params``: theta_w [rad], k_w [1/s], d_in [m], theta_in [rad], k_in [1/s], s, v_s [m/s].
    """
    push = math.sqrt(force_goal[0] ** 2 + force_goal[1] ** 2 + force_goal[2] ** 2)
    if not push > 0.0:
        tilt_window_into(speed, tilt, params[0], params[1])
        return
    n0, n1, n2 = force_goal[0] / push, force_goal[1] / push, force_goal[2] / push
    t0, t1, t2 = tilt[3], tilt[4], tilt[5]
    if n0 * error[0] + n1 * error[1] + n2 * error[2] >= params[2]:
        size = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        if size > params[3]:  # no further over
            further = max(0.0, (t0 * speed[3] + t1 * speed[4] + t2 * speed[5]) / size) / size
            speed[3] -= further * t0
            speed[4] -= further * t1
            speed[5] -= further * t2
        tilt_window_into(speed, tilt, params[3], params[4])
        return
    tilt_window_into(speed, tilt, params[0], params[1])
    l0, l1, l2 = n1 * t2 - n2 * t1, n2 * t0 - n0 * t2, n0 * t1 - n1 * t0  # n x theta
    leaning = math.sqrt(l0 * l0 + l1 * l1 + l2 * l2)
    if not leaning > 0.0:
        return
    l0, l1, l2 = l0 / leaning, l1 / leaning, l2 / leaning
    felt = min(max(n0 * wrench[0] + n1 * wrench[1] + n2 * wrench[2], 0.0), push)
    fading = max(0.0, 1.0 - (l0 * velocity[0] + l1 * velocity[1] + l2 * velocity[2]) / params[6])
    size = params[5] * felt * min(1.0, leaning / params[0]) * fading
    for i in range(6):
        slide[i] += size * (omega_bar[i, 0] * l0 + omega_bar[i, 1] * l1 + omega_bar[i, 2] * l2)


@kernel
def integrated_force_error(
    omega_bar: FloatArray, setpoint: FloatArray, wrench: FloatArray, slide: FloatArray
) -> FloatArray:
    """:func:`cosmos.osc.tilt_window.integrated_force_error`: ``Omega_bar (F_d - F_s)`` less along F_l."""
    error = matvec(omega_bar, setpoint - wrench)
    size = math.sqrt(slide[0] ** 2 + slide[1] ** 2 + slide[2] ** 2)
    if size > 0.0:
        l0, l1, l2 = slide[0] / size, slide[1] / size, slide[2] / size
        along = l0 * error[0] + l1 * error[1] + l2 * error[2]
        error[0] -= along * l0
        error[1] -= along * l1
        error[2] -= along * l2
    return error
