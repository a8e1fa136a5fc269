"""A push held against a surface, compiled (numba): :mod:`cosmos.osc.held_push`'s arithmetic.

* :func:`held_push_into`: :func:`cosmos.osc.held_push.held_push` (eq. 18 stiffened along the push);
* :func:`steel_damping_into`: :func:`cosmos.osc.held_push.steel_damping` (its damping, landed on steel);
* :func:`held_push_capped_into`: :func:`cosmos.osc.held_push.held_gains`, the two above, then
  :func:`cosmos.osc.held_push.held_push_cap` (a held push's speed limit).

``tests/runtime/test_contact_kernel.py`` checks each against its reference.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.contact import LANDED_SPEED_MPS
from cosmos.osc.held_push import RAMPED, STIFF_HELD_K_FH
from cosmos.runtime.kernels.contact import push_axis, speed_limited_push_into
from cosmos.runtime.kernels.cruise import LANDING, landing_limit

FloatArray = np.ndarray


@kernel
def held_push_into(
    feedback: FloatArray,
    force_goal: FloatArray,
    setpoint: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    force_to_acceleration: FloatArray,
    gains: FloatArray,
    integral: float,
    integrate: bool,
    dt_s: float,
) -> float:
    """:func:`cosmos.osc.held_push.held_push`, added to ``feedback`` in place.

    Args:
        feedback: F_fb, world, [N, N m]. # (6,)
        force_goal: F_d (not ramped), world: n is its direction. # (6,)
        setpoint: F_d ramped, world. # (6,)
        force_sensed: F_s, world. # (6,)
        velocity: Tool twist, world. # (6,)
        force_to_acceleration: ``Lambda^-1 Omega_bar``. # (6, 6)
        gains: ``(k_fh, k_ih, k_vh, integral_limit)``. # (4,)
        integral: The push error's integral along n so far, in [N s].
        integrate: Whether it grows this tick (touching and the goal reached).
        dt_s: Servo period, in [s].

    Returns:
        The updated integral, in [N s].
    """
    n0, n1, n2, inverse_mass = push_axis(force_goal, force_to_acceleration)
    if not inverse_mass > 0.0:
        return integral
    error = n0 * (setpoint[0] - force_sensed[0]) + n1 * (setpoint[1] - force_sensed[1])
    error += n2 * (setpoint[2] - force_sensed[2])
    if integrate:
        integral = min(max(integral + error * dt_s, -gains[3]), gains[3])
    along = n0 * velocity[0] + n1 * velocity[1] + n2 * velocity[2]
    added = gains[0] * error + gains[1] * integral - gains[2] * along / inverse_mass
    feedback[0] += added * n0
    feedback[1] += added * n1
    feedback[2] += added * n2
    return integral


@kernel
def ramp_over(force_goal: FloatArray, setpoint: FloatArray) -> bool:
    """:func:`cosmos.osc.held_push.ramp_over`: the ramped F_d has reached the segment's."""
    gap = 0.0
    size = 0.0
    for i in range(3):
        gap += (force_goal[i] - setpoint[i]) * force_goal[i]
        size += force_goal[i] * force_goal[i]
    return gap <= RAMPED * size


@kernel
def steel_damping_into(
    feedback: FloatArray,
    force_goal: FloatArray,
    velocity: FloatArray,
    force_to_acceleration: FloatArray,
    k_vf: float,
    band: float,
) -> FloatArray:
    """:func:`cosmos.osc.held_push.steel_damping`: ``feedback`` in place; returns the damped twist. # (6,)."""
    n0, n1, n2, inverse_mass = push_axis(force_goal, force_to_acceleration)
    damped = velocity.copy()
    if not inverse_mass > 0.0:
        return damped
    along = n0 * velocity[0] + n1 * velocity[1] + n2 * velocity[2]
    beyond = along - band if along > band else (along + band if along < -band else 0.0)
    back = k_vf * (along - beyond) / inverse_mass
    for i, ni in ((0, n0), (1, n1), (2, n2)):
        feedback[i] += back * ni
        damped[i] += (beyond - along) * ni
    return damped


@kernel
def held_push_capped_into(
    feedback: FloatArray,
    held_integral: FloatArray,
    force_goal: FloatArray,
    setpoint: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    error: FloatArray,
    force_to_acceleration: FloatArray,
    gains: FloatArray,
    integrate: bool,
    dt_s: float,
    max_speed: float,
    speeds: FloatArray,
    scalars: FloatArray,
) -> bool:
    """:func:`held_push_into` (on steel with :func:`steel_damping_into`), then its speed limit, in place.

    :func:`cosmos.osc.held_push.held_gains` once landed on steel (a landing set, ``integrate``),
    :func:`cosmos.osc.held_push.steel_damping` once held there (:func:`cosmos.osc.held_push.held_on_steel`),
    :func:`cosmos.osc.held_push.held_push`, then
    :func:`cosmos.osc.held_push.held_push_cap` on the sensed twist.

    Args:
        feedback: F_fb, world, [N, N m]. # (6,)
        held_integral: The held push's integral [N s] at 0, in and out (0 where the cap binds). # (>= 1,)
        force_goal: F_d (not ramped), world. # (6,)
        setpoint: F_d ramped, world. # (6,)
        force_sensed: F_s, world. # (6,)
        velocity: Tool twist, world. # (6,)
        error: ``x - x_d``, world. # (6,)
        force_to_acceleration: ``Lambda^-1 Omega_bar``. # (6, 6)
        gains: ``(k_fh, k_ih, k_vh, integral_limit)``; landed on steel (a landing set, ``integrate``)
            ``k_fh`` at most STIFF_HELD_K_FH. # (4,)
        integrate: Whether the held integral grows this tick.
        dt_s: Servo period, in [s].
        max_speed: ``V_max``, the statement's SPEED [m/s].
        speeds: ``(k_vf [1/s], kv [1/s])``. # (>= 2,)
        scalars: The servo's scalars; the landing's ``(s_l, v_l, a)`` at kernels.cruise's LANDING read.

    Returns:
        Whether the cap binds (the force loop's own integral is then the caller's to hold).
    """
    landing = scalars[LANDING : LANDING + 3]
    held, damped = gains.copy(), velocity
    if landing[1] > 0.0 and integrate:  # landed on steel (cosmos.osc.held_push.held_gains)
        held[0] = min(held[0], STIFF_HELD_K_FH)
    if landing[1] > 0.0 and integrate and ramp_over(force_goal, setpoint):  # osc.held_push.held_on_steel
        damped = steel_damping_into(
            feedback, force_goal, velocity, force_to_acceleration, speeds[0], LANDED_SPEED_MPS
        )
    held_integral[0] = held_push_into(
        feedback,
        force_goal,
        setpoint,
        force_sensed,
        damped,
        force_to_acceleration,
        held,
        held_integral[0],
        integrate,
        dt_s,
    )
    n0, n1, n2, inverse_mass = push_axis(force_goal, force_to_acceleration)
    if not inverse_mass > 0.0:
        return False
    to_go = -(n0 * error[0] + n1 * error[1] + n2 * error[2]) - landing[0]
    limit, brake = landing_limit(max_speed, to_go, landing[1], landing[2])
    if not n0 * velocity[0] + n1 * velocity[1] + n2 * velocity[2] > 0.0:  # at rest: stiction's to break
        return False
    capped, _ = speed_limited_push_into(
        feedback,
        force_goal,
        force_sensed,
        velocity,
        force_to_acceleration,
        limit,
        speeds[1],
        speeds[0],
        -brake,
    )
    if capped:  # the surface it was learnt against is lost
        held_integral[0] = 0.0
    return capped
