"""A held contact's sliding friction, measured, compensated toward the motion axes' intent (eq. 17-18).

Eq. 17-18 decouple the end effector in free space: with ``F = Lambda F*_m + mu + p + F_a`` the tool
moves as a unit mass on its motion axes, ``xdd = F*_m``. Sliding on a surface, the surface's
Coulomb friction ``f_s = -mu_s N xd / |xd|`` acts on the tool too, and the arm moves as
``xdd = F*_m + Lambda^-1 f_s``. Lambda^-1 is not isotropic (the PUMA's tool 40 mm above the table
in a frame turned 30 deg about z: 0.51, 0.14 and 0.09 1/kg on its diagonal, up to 0.10 off it), so
the friction does not only hold the tool back along the slide, which eq. 19's tracking and its
integral (:mod:`cosmos.osc.integral_action`) answer: it pushes the tool across the slide too. A
16 N friction (0.8 x 20 N) gave the tool 2.3 m/s^2 across, which eq. 19's ``-kp e`` balanced only
with a steady error, 2.2 mm off its line for the whole slide (the wrist sensing no force across:
the push across is Lambda^-1's, not the surface's); then the slide's integral, at the
reference's end, had to beat the static friction along and across, and the tool it broke loose
hunted +-2 mm at up to 42 mm/s about its goal: the SLIDE failed.

The wrist sensor measures that friction: the wrench the tool applies on the motion-controlled
translations (``Omega f``: the tangent plane of a held contact). Its coefficient is taken against
the push's setpoint ``|F_d|`` (against the sensed push, whose dips make its peaks, a light push
rippled), learnt while the tool slides faster than ``v_s`` and, until its first slide on the
contact, from rest: static friction holds any smaller force, so the tangential force the tool holds
still while its intent asks it to move is a lower bound of the coefficient::

    mu_s <- mu_s + r dt (|Omega f| / |F_d| - mu_s)      sliding (|Omega xd| > v_s)
    mu_s <- max(mu_s, |Omega f| / |F_d|)                 not yet slid, asked to move

clamped to ``[0, mu_max]``. Eq. 17 gains the force the friction will take, toward where the tool
moves or is told to move, as the joints' Coulomb compensation (:mod:`cosmos.osc.friction`, with
its look-ahead L and the commanded speed ``xd_c``)::

    F = Lambda F*_m + mu + p + F_a + F_s
    s = Omega (xd + L F*_fb + xd_c)
    F_s = c max(mu_s |F_d| - f_0, 0) clip(|s| / v_c, 0, 1) s / |s|      (low-passed as the joints')

with ``F*_fb`` eq. 19's feedback without the slide's integral (the integral's push in the intent
drove the compensation, and the compensation the integral, about the goal), ``c < 1`` the share
compensated and ``f_0`` a floor left to eq. 19 and its integral: a table's 0.3 at 5 N (1.5 N) is
what they answer well, and compensating it made a 5 N slide at 5 mm/s ripple its push (84-86 % of
the slide within 15 %, for 99.8 % without) on the realistic plant. The tool slides as a unit mass
again, its error across corrected by eq. 19 as in free space; at the slide's end a tool that static
friction holds within ``v_c / (L kp)`` of its goal (0.6 mm) stays, one further off is set sliding.
``v_s`` is above the realistic velocity observer's noise at rest (at 5 mm/s that noise counted as
the first slide, the lower bound was lost, and a 30 N slide at friction 1.0 broke loose late,
caught up at 40-80 mm/s and chattered on the table up to a 130 N protective stop). The coefficient
is kept while the contact is held (the next SLIDE starts with it) and forgotten with it.

The compiled kernel :mod:`cosmos.runtime.kernels.surface_friction` runs the same arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cosmos.osc._types import FloatArray


@dataclass(frozen=True)
class SurfaceFrictionGains:
    """The surface friction's learning and compensation.

    Attributes:
        full_speed_mps: v_c, the intent's speed at which the whole friction is compensated, [m/s].
        sliding_mps: v_s, the speed along the surface above which the tool slides, [m/s].
        rate_per_s: r, the rate at which the coefficient follows what the tool slides on, [1/s].
        share: c, the share of the learnt friction compensated, [1].
        max_coefficient: mu_max, the largest coefficient learnt, [1].
        floor_n: f_0, the friction left to eq. 19 and its integral, [N].
    """

    full_speed_mps: float = 0.005
    sliding_mps: float = 0.010
    rate_per_s: float = 5.0
    share: float = 0.9
    max_coefficient: float = 1.5
    floor_n: float = 2.0


SURFACE_FRICTION = SurfaceFrictionGains()
"""The servo's (:mod:`cosmos.runtime.kernels.surface_friction` compiles them in)."""


def split_on_surface(vector: FloatArray, omega_bar: FloatArray) -> tuple[FloatArray, FloatArray]:
    """A translation's parts along the surface (``Omega``) and along the push (``Omega_bar``).

    Args:
        vector: World, 3 or more entries (the first three used). # (>= 3,)
        omega_bar: Force-controlled projector, world (its translation block used). # (6, 6)

    Returns:
        ``(Omega v, Omega_bar v)``, world. # (3,), (3,)
    """
    along_push = np.asarray(omega_bar)[:3, :3].dot(np.asarray(vector)[:3])
    return np.asarray(vector)[:3] - along_push, along_push


def surface_intent(
    velocity: FloatArray,
    motion: FloatArray,
    commanded_speed: FloatArray,
    omega_bar: FloatArray,
    lookahead_s: float,
) -> FloatArray:
    """``s = Omega (xd + L F*_m + xd_c)``: where the tool moves, or is told to move, on the surface. # (3,).

    Args:
        velocity: Tool twist, world, [m/s] then [rad/s]. # (6,)
        motion: F*_m, world, [m/s^2] then [rad/s^2]. # (6,)
        commanded_speed: An operational speed commanded outright (a tracked reference's xd_d), world. # (6,)
        omega_bar: Force-controlled projector, world. # (6, 6)
        lookahead_s: L, in [s].
    """
    speed = np.asarray(velocity)[:3] + lookahead_s * np.asarray(motion)[:3] + np.asarray(commanded_speed)[:3]
    return split_on_surface(speed, omega_bar)[0]


def learn_surface_friction(
    coefficient: float,
    slid: bool,
    wrench: FloatArray,
    velocity: FloatArray,
    intent: FloatArray,
    omega_bar: FloatArray,
    push_n: float,
    dt_s: float,
    gains: SurfaceFrictionGains,
) -> tuple[float, bool]:
    """One tick of the surface's friction coefficient ``mu_s`` (the module's docstring).

    Args:
        coefficient: mu_s so far.
        slid: Whether the tool has slid on this contact yet.
        wrench: The wrench the tool applies, world, [N] then [N m]. # (6,)
        velocity: Tool twist, world. # (6,)
        intent: :func:`surface_intent`. # (3,)
        omega_bar: Force-controlled projector, world. # (6, 6)
        push_n: ``|F_d|``, the push's setpoint, [N].
        dt_s: Servo period, in [s].
        gains: The gains.

    Returns:
        The new ``(mu_s, slid)``.
    """
    if not push_n > 0.0:
        return coefficient, slid
    ratio = float(np.linalg.norm(split_on_surface(wrench, omega_bar)[0])) / push_n
    if float(np.linalg.norm(split_on_surface(velocity, omega_bar)[0])) > gains.sliding_mps:
        coefficient, slid = coefficient + gains.rate_per_s * dt_s * (ratio - coefficient), True
    elif not slid and float(np.linalg.norm(intent)) >= gains.full_speed_mps:
        coefficient = max(coefficient, ratio)
    return min(max(coefficient, 0.0), gains.max_coefficient), slid


def surface_friction_force(
    previous: FloatArray,
    coefficient: float,
    push_n: float,
    intent: FloatArray,
    blend: float,
    gains: SurfaceFrictionGains,
) -> FloatArray:
    """One tick of ``F_s``, low-passed: ``F_s + beta (c mu_s |F_d| clip(|s| / v_c, 0, 1) s / |s| - F_s)``.

    Args:
        previous: F_s of the previous tick, world, [N]. # (3,)
        coefficient: mu_s.
        push_n: ``|F_d|``, the push's setpoint, [N].
        intent: s (:func:`surface_intent`), world, [m/s]. # (3,)
        blend: beta, the low-pass's share of the new target per tick (the joints' Coulomb one's).
        gains: The gains.

    Returns:
        F_s, world, [N]; added to eq. 17's F at the tool point. # (3,)
    """
    size = float(np.linalg.norm(intent))
    target = np.zeros(3)
    if size > 0.0:
        friction = max(coefficient * push_n - gains.floor_n, 0.0)
        level = gains.share * friction * min(size / gains.full_speed_mps, 1.0)
        target = level * np.asarray(intent) / size
    return np.asarray(previous) + blend * (target - np.asarray(previous))
