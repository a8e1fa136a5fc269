"""Motion commands of the unit-mass end effector (seed eq. 19-21, 36-37); timed trajectories.

Every command here is ``F*_m``: an acceleration-like vector, in [m/s^2] then
[rad/s^2], world axes, that eq. 18 turns into a force with ``Lambda``. The
operational error is ``x - x_d`` as defined by
:func:`cosmos.osc.orientation.pose_error` (``(p - p_d, log(R R_d^T))``), and
velocities are twists ``(v, w)`` of the tool point in world axes, the
quantities the geometric Jacobian's rows give.

Gains are floats or per-axis arrays # (6,) in world axes (elementwise).

Redundancy (eq. 34-38): with ``xi_q > 0`` the commands add ``xi_q xd``
(eq. 36, 37); pair them with the joint torque ``-xi_q A qd``, or, equivalently,
use ``xi_q = 0`` here and add :func:`cosmos.osc.dynamics.null_space_damping`
(eq. 34). Either way the closed loop dissipates with eq. 38.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.osc.orientation import so3_exp, so3_log

Gain = float | FloatArray


def tracking_command(
    error: FloatArray,
    velocity: FloatArray,
    velocity_desired: FloatArray,
    acceleration_desired: FloatArray,
    kp: Gain,
    kv: Gain,
    xi_q: float = 0.0,
) -> FloatArray:
    """Trajectory tracking, eq. 19 (eq. 36 with xi_q): ``xdd_d - kp e - kv (xd - xd_d) + xi_q xd``.

    Args:
        error: ``x - x_d`` from ``pose_error``, in [m] and [rad]. # (6,)
        velocity: Tool twist ``xd``, in [m/s] and [rad/s]. # (6,)
        velocity_desired: ``xd_d``. # (6,)
        acceleration_desired: ``xdd_d``, in [m/s^2] and [rad/s^2]. # (6,)
        kp: Position gain, in [1/s^2].
        kv: Velocity gain (the seed's xi), in [1/s].
        xi_q: Null-space damping gain of eq. 34-36, in [1/s].

    Returns:
        F*_m. # (6,)
    """
    command = acceleration_desired - kp * error - kv * (velocity - velocity_desired)
    return command + xi_q * velocity if xi_q else command


def _speed_limited(desired: list[float], max_speed: float, max_angular_speed: float) -> list[float]:
    """Eq. 21's ``nu``, applied to the linear and the angular part separately."""
    vx, vy, vz, wx, wy, wz = desired
    linear = math.sqrt(vx * vx + vy * vy + vz * vz)
    angular = math.sqrt(wx * wx + wy * wy + wz * wz)
    nu = 1.0 if linear <= max_speed else max_speed / linear
    nu_w = 1.0 if angular <= max_angular_speed else max_angular_speed / angular
    return [nu * vx, nu * vy, nu * vz, nu_w * wx, nu_w * wy, nu_w * wz]


def ramped_speed_limit(limit: float, start_speed: float, acceleration: float, elapsed_s: float) -> float:
    """Eq. 21's V_max from rest, ramped: ``min(V_max, v_0 + a t)``.

    Eq. 20-21 as the seed writes them command ``kv (nu xd_d - xd)``: from rest, far from
    the goal, a step of ``kv V_max`` (10 m/s^2 at 0.25 m/s with kv = 40, twice the arms'
    declared 5 m/s^2; 5-6 N m at the drives within 3 ms). With the limit ramped at the
    arm's acceleration ``a`` from the speed ``v_0`` the tool had when the motion began, a
    unit mass at rest follows ``xd = a (t - (1 - e^{-kv t}) / kv)`` and is commanded
    ``a (1 - e^{-kv t})``: never more than ``a``, rising from zero.

    Args:
        limit: V_max, in [m/s] (or [rad/s]).
        start_speed: v_0, the speed when the motion began, in the same unit.
        acceleration: a, in [m/s^2] (or [rad/s^2]).
        elapsed_s: t, time since the motion began, in [s].

    Returns:
        The speed limit now.
    """
    return min(limit, start_speed + acceleration * max(elapsed_s, 0.0))


GOAL_RAMP_MIN_S = 0.3
"""A free MOVE's goal motion reaches its SPEED no sooner than this after it starts [s]."""


def goal_ramp_acceleration(limit: float, acceleration: float) -> float:
    """The acceleration at which a MOVE's eq. 21 limit ramps up: ``min(a, V_max / 0.3 s)``.

    A goal motion's cruise holds its SPEED against the force the controller's model does not
    explain with an integral (:mod:`cosmos.osc.cruise_speed`) that learns it only once the
    tool moves; before that eq. 20's velocity servo leaves a speed error of up to ``d / (e p)``
    for a step ``d`` of it (the loop's double root ``p = kv / 2``, 20 /s: peak at 50 ms).
    On the realistic plant ``d`` is up to 0.3 m/s^2, 5.5 mm/s whatever the SPEED: at SPEED
    20 mm/s a MOVE ran at 24.5 mm/s over 20 ms in its first 0.1 s (seed 0), ramped at the
    arm's 5 m/s^2. Ramped over :data:`GOAL_RAMP_MIN_S` (the ramps of a cruise, :func:`cruise_ramp_s`)
    the limit is a sixth of the SPEED when that error peaks, and the integral has settled when
    it reaches the SPEED. The arm's acceleration still bounds the fast ones.

    Args:
        limit: V_max, in [m/s].
        acceleration: The arm's tool acceleration, in [m/s^2].
    """
    return min(acceleration, limit / GOAL_RAMP_MIN_S)


def on_the_line(desired: FloatArray, line: FloatArray, max_speed: float) -> FloatArray:
    """Eq. 21's translation kept on its line: the speed limit taken from the travel along it.

    Eq. 21 scales the whole ``xd_d = (kp/kv)(x_d - x)`` to ``V_max``: far from the goal a
    deviation ``e`` from the straight line is then answered with ``V_max e / |x_d - x|``, a
    stiffness that vanishes with the distance (the realistic Panda's tool sagged 2.4 mm off
    a 0.4 m line under its drawn model error, where a hold's stiffness leaves 0.3 mm). Here
    the part across the line ``u`` keeps its full ``(kp/kv)`` (within ``V_max``) and the
    part along it gets the rest of ``V_max``: on the line this is eq. 21 exactly.

    Args:
        desired: ``xd_d``, unlimited, in [m/s]. # (3,)
        line: Unit vector from the motion's start to its goal (zeros: no line). # (3,)
        max_speed: V_max, in [m/s].

    Returns:
        The limited translation speed, in [m/s]. # (3,)
    """
    desired = np.asarray(desired, dtype=float)
    norm = float(np.linalg.norm(desired))
    if norm <= max_speed:
        return desired
    along = float(desired.dot(line))
    across = desired - along * np.asarray(line)
    width = float(np.linalg.norm(across))
    if not line.any():
        return desired * (max_speed / norm)
    if width >= max_speed:
        return across * (max_speed / width) if width > 0.0 else np.zeros(3)
    return across + math.copysign(math.sqrt(max_speed**2 - width**2), along) * np.asarray(line)


def goal_velocity(
    error: FloatArray,
    kp: Gain,
    kv: Gain,
    max_speed: float,
    max_angular_speed: float,
    line: FloatArray | None = None,
) -> FloatArray:
    """Speed-limited desired velocity of eq. 21: ``nu (kp/kv)(x_d - x)``.

    The seed's ``nu = min(1, V_max/|xd_d|)`` is applied twice, to the translation
    with ``max_speed`` and to the rotation with ``max_angular_speed``, so each
    part points at its goal (a straight line; a fixed rotation axis) and neither
    limit depends on the units of the other. With ``line`` the translation keeps to
    it (:func:`on_the_line`).

    Args:
        error: ``x - x_d``, in [m] and [rad]. # (6,)
        kp: Position gain, in [1/s^2].
        kv: Velocity gain, in [1/s].
        max_speed: V_max for the tool point, in [m/s].
        max_angular_speed: The same for the rotation, in [rad/s].
        line: Unit vector from the motion's start to its goal, or None. # (3,)

    Returns:
        ``nu xd_d``, in [m/s] and [rad/s]. # (6,)
    """
    desired = ((-kp / kv) * error).tolist()
    limited = np.array(_speed_limited(desired, max_speed, max_angular_speed))
    if line is not None:
        limited[:3] = on_the_line(np.array(desired[:3]), np.asarray(line, dtype=float), max_speed)
    return limited


def goal_command(
    error: FloatArray,
    velocity: FloatArray,
    kp: Gain,
    kv: Gain,
    max_speed: float,
    max_angular_speed: float,
    xi_q: float = 0.0,
    line: FloatArray | None = None,
) -> FloatArray:
    """Goal position with a speed limit, eq. 20-21 (37 with xi_q): ``-kv (xd - nu xd_d) + xi_q xd``.

    Far from the goal the tool travels in a straight line at ``max_speed`` (and
    turns about a fixed axis at ``max_angular_speed``); near it, the command is
    ``-kp (x - x_d) - kv xd``.

    Args:
        error: ``x - x_d``, in [m] and [rad]. # (6,)
        velocity: Tool twist ``xd``, in [m/s] and [rad/s]. # (6,)
        kp: Position gain, in [1/s^2].
        kv: Velocity gain, in [1/s].
        max_speed: Speed limit of the tool point, in [m/s].
        max_angular_speed: Angular speed limit, in [rad/s].
        xi_q: Null-space damping gain of eq. 34-37, in [1/s].
        line: The line the tool point keeps to (:func:`goal_velocity`), or None. # (3,)

    Returns:
        F*_m. # (6,)
    """
    command = kv * (goal_velocity(error, kp, kv, max_speed, max_angular_speed, line) - velocity)
    return command + xi_q * velocity if xi_q else command


def min_jerk(t_s: float, duration_s: float) -> tuple[float, float, float]:
    """Minimum-jerk (quintic) time scaling ``s = 10 u^3 - 15 u^4 + 6 u^5``, ``u = t/T`` in [0, 1].

    Zero velocity and acceleration at both ends.

    Args:
        t_s: Time since the start, in [s].
        duration_s: Total duration T, in [s], > 0.

    Returns:
        ``(s, ds/dt, d2s/dt2)`` in [1], [1/s], [1/s^2].
    """
    if t_s <= 0.0:
        return 0.0, 0.0, 0.0
    if t_s >= duration_s:
        return 1.0, 0.0, 0.0
    u = t_s / duration_s
    v = 1.0 - u
    s = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
    return (
        s,
        30.0 * u * u * v * v / duration_s,
        60.0 * u * v * (1.0 - 2.0 * u) / (duration_s * duration_s),
    )


CRUISE_ACCELERATION_MPS2 = 0.5
"""Acceleration of a cruising trajectory's ramps (SLIDE), in [m/s^2]."""
CRUISE_RAMP_MIN_S = 0.3
"""Shortest ramp of a cruising trajectory, in [s]."""


def cruise_ramp_s(speed_mps: float) -> float:
    """Duration of a cruising trajectory's speed ramps: ``max(0.3 s, V / a)``."""
    return max(CRUISE_RAMP_MIN_S, speed_mps / CRUISE_ACCELERATION_MPS2)


def cruise_duration(distance_m: float, speed_mps: float) -> float:
    """Duration of a cruise over ``distance_m`` at ``speed_mps``: ``D / V + ramp`` (two ramps at least)."""
    ramp = cruise_ramp_s(speed_mps)
    return max(distance_m / speed_mps + ramp, 2.0 * ramp)


def cruise(t_s: float, duration_s: float, ramp_s: float) -> tuple[float, float, float]:
    """Time scaling that cruises: cosine speed ramps of ``ramp_s`` at both ends, constant between.

    ``ds/dt = v (1 - cos(pi t / ramp)) / 2`` over the first ramp, ``v`` in the middle,
    the mirror image at the end, with ``v = 1 / (T - ramp)`` so that s goes from 0 to 1.
    Zero speed and acceleration at both ends. A SLIDE of D at speed V uses
    ``T = D / V + ramp`` (:func:`cruise_duration`): between its ramps it moves at V,
    where minimum jerk (:func:`min_jerk`), peaking at V, would average 53 % of it.

    Args:
        t_s: Time since the start, in [s].
        duration_s: Total duration T, in [s]; at least ``2 ramp_s``.
        ramp_s: Duration of each ramp, in [s], > 0.

    Returns:
        ``(s, ds/dt, d2s/dt2)`` in [1], [1/s], [1/s^2].
    """
    if t_s <= 0.0:
        return 0.0, 0.0, 0.0
    if t_s >= duration_s:
        return 1.0, 0.0, 0.0
    ramp = min(ramp_s, 0.5 * duration_s)
    v = 1.0 / (duration_s - ramp)
    mirrored = t_s > duration_s - ramp
    u = duration_s - t_s if mirrored else t_s
    if u >= ramp:
        s, sd, sdd = v * (0.5 * ramp + (u - ramp)), v, 0.0
    else:
        phase = math.pi * u / ramp
        s = v * (0.5 * u - ramp / (2.0 * math.pi) * math.sin(phase))
        sd = 0.5 * v * (1.0 - math.cos(phase))
        sdd = 0.5 * v * math.pi / ramp * math.sin(phase)
    return (1.0 - s, sd, -sdd) if mirrored else (s, sd, sdd)


class PoseSample(NamedTuple):
    """Desired pose, twist and its derivative at one instant; world axes."""

    position: FloatArray  # (3,) [m]
    rotation_to_world: FloatArray  # (3, 3)
    velocity: FloatArray  # (6,) [m/s, rad/s]
    acceleration: FloatArray  # (6,) [m/s^2, rad/s^2]


@dataclass(frozen=True)
class PoseTrajectory:
    """A timed move (``MOVE ... IN t``): straight line, fixed-axis rotation, minimum-jerk timing.

    ``p(t) = p0 + s(t) (p1 - p0)`` and ``R(t) = exp(s(t) phi) R0`` with
    ``phi = log(R1 R0^T)`` (world axes), so the angular velocity is exactly
    ``ds/dt phi`` (a slerp). Track it with :func:`tracking_command` (eq. 19).

    Attributes:
        start_position: p0, in [m]. # (3,)
        start_rotation_to_world: R0. # (3, 3)
        displacement: p1 - p0, in [m]. # (3,)
        rotation_vector: phi, in [rad], world axes. # (3,)
        duration_s: T, in [s].
        cruise_ramp_s: None for minimum-jerk timing; else the ramps of :func:`cruise`, [s].
    """

    start_position: FloatArray
    start_rotation_to_world: FloatArray
    displacement: FloatArray
    rotation_vector: FloatArray
    duration_s: float
    cruise_ramp_s: float | None = None

    @classmethod
    def between(
        cls,
        start_position: FloatArray,
        start_rotation_to_world: FloatArray,
        end_position: FloatArray,
        end_rotation_to_world: FloatArray,
        duration_s: float,
        cruise_speed_mps: float | None = None,
        cruise_angular_speed_rad_s: float | None = None,
    ) -> PoseTrajectory:
        """The move from a start pose to an end pose in ``duration_s`` seconds.

        With ``cruise_speed_mps`` the tool point cruises at that speed
        (:func:`cruise`) and the duration is :func:`cruise_duration` of the
        distance (``duration_s`` is then ignored). With ``cruise_angular_speed_rad_s``
        too, a rotation that would turn faster than it stretches the cruise instead: the
        tool point then cruises slower (a rotation with little travel keeps its speed limit).

        Raises:
            ValueError: If the duration is not positive.
        """
        ramp = None
        if cruise_speed_mps is not None:
            distance = float(np.linalg.norm(np.asarray(end_position, dtype=float) - start_position))
            if cruise_angular_speed_rad_s is not None:
                angle = float(np.linalg.norm(so3_log(end_rotation_to_world.dot(start_rotation_to_world.T))))
                distance = max(distance, angle * cruise_speed_mps / cruise_angular_speed_rad_s)
            ramp = cruise_ramp_s(cruise_speed_mps)
            duration_s = cruise_duration(distance, cruise_speed_mps)
        if not duration_s > 0.0:
            raise ValueError(f"PoseTrajectory: duration_s must be > 0, got {duration_s}")
        return cls(
            start_position=np.array(start_position, dtype=float),
            start_rotation_to_world=np.array(start_rotation_to_world, dtype=float),
            displacement=np.asarray(end_position, dtype=float) - start_position,
            rotation_vector=so3_log(end_rotation_to_world.dot(start_rotation_to_world.T)),
            duration_s=float(duration_s),
            cruise_ramp_s=ramp,
        )

    def sample(self, t_s: float) -> PoseSample:
        """Desired pose, twist and acceleration ``t_s`` seconds after the start (held after T)."""
        if self.cruise_ramp_s is None:
            s, sd, sdd = min_jerk(t_s, self.duration_s)
        else:
            s, sd, sdd = cruise(t_s, self.duration_s, self.cruise_ramp_s)
        px, py, pz = self.start_position.tolist()
        dx, dy, dz = self.displacement.tolist()
        fx, fy, fz = self.rotation_vector.tolist()
        turn = so3_exp(s * self.rotation_vector)
        return PoseSample(
            position=np.array((px + s * dx, py + s * dy, pz + s * dz)),
            rotation_to_world=turn.dot(self.start_rotation_to_world),
            velocity=np.array((sd * dx, sd * dy, sd * dz, sd * fx, sd * fy, sd * fz)),
            acceleration=np.array((sdd * dx, sdd * dy, sdd * dz, sdd * fx, sdd * fy, sdd * fz)),
        )
