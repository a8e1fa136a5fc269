"""Search patterns of INSERT ... SEARCH: where the tool goes across the insertion axis.

A search is a timed trajectory of the two lateral translations of the INSERT's task
frame, tracked with eq. 19 (``xdd_d - kp e - kv (xd - xd_d)``) on those axes while
the insertion axis stays force-controlled (the complement of Omega): the same law
that SLIDE tracks along a surface. Each pattern is a pure function of its own
parameter here; :class:`SearchTrajectory` times it (cosine speed ramps at both
ends, constant tangential speed between: :func:`cosmos.osc.motion.cruise`) and
places it in the world.

- Spiral (ABB's FCRefSpiral): the Archimedean spiral ``r(theta) = pitch theta / 2 pi``,
  from the start out to ``radius``, moved at a constant speed along its arc.
- Lissajous (KUKA's): ``(r sin(a phi), r sin(b phi))`` with ``b = a + 1``, over one
  period ``phi`` in [0, 2 pi]; ``a = ceil(pi r / pitch)`` so that its strands cross
  the axes at most ``pitch`` apart. Moved at a constant speed along its arc too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.osc.motion import PoseSample, cruise, cruise_duration, cruise_ramp_s


def spiral_point(theta: float, pitch_m: float) -> tuple[float, float]:
    """Point of the Archimedean spiral ``r = pitch theta / 2 pi`` at angle ``theta`` [m]."""
    r = pitch_m * theta / (2.0 * math.pi)
    return r * math.cos(theta), r * math.sin(theta)


def spiral_arc_length(theta: float, pitch_m: float) -> float:
    """Arc of the spiral from its centre to ``theta``: ``a/2 (theta sqrt(1+theta^2) + asinh theta)``."""
    a = pitch_m / (2.0 * math.pi)
    return 0.5 * a * (theta * math.sqrt(1.0 + theta * theta) + math.asinh(theta))


def spiral_angle_at(length_m: float, pitch_m: float, guess: float = 0.0) -> float:
    """The angle at which the spiral's arc from its centre is ``length_m`` long (Newton)."""
    if length_m <= 0.0:
        return 0.0
    a = pitch_m / (2.0 * math.pi)
    theta = max(guess, math.sqrt(2.0 * length_m / a))  # s ~ a theta^2 / 2 overshoots: start above
    for _ in range(30):
        step = (spiral_arc_length(theta, pitch_m) - length_m) / (a * math.sqrt(1.0 + theta * theta))
        theta -= step
        if abs(step) < 1e-12:
            break
    return theta


def lissajous_lobes(radius_m: float, pitch_m: float) -> int:
    """The Lissajous frequency ``a`` (``b = a + 1``) whose strands are at most ``pitch`` apart."""
    return max(1, math.ceil(math.pi * radius_m / pitch_m))


def lissajous_point(phi: float, radius_m: float, lobes: int) -> tuple[float, float]:
    """``(r sin(a phi), r sin((a + 1) phi))`` [m]."""
    return radius_m * math.sin(lobes * phi), radius_m * math.sin((lobes + 1) * phi)


@dataclass(frozen=True)
class SpiralPath:
    """The spiral from its centre out to ``radius_m``, by arc length."""

    radius_m: float
    pitch_m: float

    @property
    def length_m(self) -> float:
        """Total arc length, in [m]."""
        return spiral_arc_length(2.0 * math.pi * self.radius_m / self.pitch_m, self.pitch_m)

    def at(self, length_m: float) -> tuple[float, float]:
        """The offset at arc length ``length_m`` (clamped to the ends), in [m]."""
        theta_end = 2.0 * math.pi * self.radius_m / self.pitch_m
        theta = min(spiral_angle_at(min(length_m, self.length_m), self.pitch_m), theta_end)
        return spiral_point(theta, self.pitch_m)


@dataclass(frozen=True, eq=False)
class LissajousPath:
    """One period of the Lissajous figure, by arc length (its angle tabulated against its arc).

    Attributes:
        radius_m: Amplitude r of both axes, in [m].
        lobes: a (and b = a + 1).
        arc_m: Arc length at each tabulated angle, in [m]. # (n,)
        phi: The angles. # (n,)
    """

    radius_m: float
    lobes: int
    arc_m: FloatArray
    phi: FloatArray

    @classmethod
    def of(cls, radius_m: float, pitch_m: float) -> LissajousPath:
        """The figure whose strands are at most ``pitch_m`` apart."""
        lobes = lissajous_lobes(radius_m, pitch_m)
        phi = np.linspace(0.0, 2.0 * math.pi, 4000 * (lobes + 1))
        x, y = radius_m * np.sin(lobes * phi), radius_m * np.sin((lobes + 1) * phi)
        steps = np.hypot(np.diff(x), np.diff(y))
        return cls(radius_m, lobes, np.concatenate(((0.0,), np.cumsum(steps))), phi)

    @property
    def length_m(self) -> float:
        """Total arc length, in [m]."""
        return float(self.arc_m[-1])

    def at(self, length_m: float) -> tuple[float, float]:
        """The offset at arc length ``length_m`` (clamped to the ends), in [m]."""
        return lissajous_point(float(np.interp(length_m, self.arc_m, self.phi)), self.radius_m, self.lobes)


PatternPath = SpiralPath | LissajousPath


@dataclass(frozen=True)
class SearchTrajectory:
    """A pattern placed in the world and timed: ``p(t) = p0 + U path(s(t))``, fixed orientation.

    Attributes:
        start_position: p0, the tool point when the search starts, in [m]. # (3,)
        rotation_to_world: The orientation held, tool to world. # (3, 3)
        lateral_world: U, the world directions of the pattern's two axes (columns). # (3, 2)
        path: The pattern by arc length.
        speed_mps: The tangential speed between the ramps, in [m/s].
        duration_s: The whole pattern's time, ramps included, in [s].
    """

    start_position: FloatArray
    rotation_to_world: FloatArray
    lateral_world: FloatArray
    path: PatternPath
    speed_mps: float
    duration_s: float

    @classmethod
    def of(
        cls,
        path: PatternPath,
        start_position: FloatArray,
        rotation_to_world: FloatArray,
        lateral_world: FloatArray,
        speed_mps: float,
    ) -> SearchTrajectory:
        """The pattern from the given pose, at ``speed_mps`` along its arc."""
        duration = cruise_duration(path.length_m, speed_mps)
        return cls(
            np.array(start_position, dtype=float),
            np.array(rotation_to_world, dtype=float),
            np.array(lateral_world, dtype=float),
            path,
            speed_mps,
            duration,
        )

    def offset(self, t_s: float) -> FloatArray:
        """The pattern's lateral offset at ``t_s`` after the start, in its own axes, [m]. # (2,)."""
        s, _, _ = cruise(t_s, self.duration_s, cruise_ramp_s(self.speed_mps))
        return np.array(self.path.at(s * self.path.length_m))

    def sample(self, t_s: float, dt_s: float = 1e-3) -> PoseSample:
        """Desired pose, twist and acceleration (central differences over ``dt_s``)."""
        before, now, after = (self.offset(t_s + k * dt_s) for k in (-1, 0, 1))
        u = self.lateral_world
        velocity = np.zeros(6)
        acceleration = np.zeros(6)
        velocity[:3] = u.dot((after - before) / (2.0 * dt_s))
        acceleration[:3] = u.dot((after - 2.0 * now + before) / (dt_s * dt_s))
        return PoseSample(self.start_position + u.dot(now), self.rotation_to_world, velocity, acceleration)


def toward_the_hole(
    rotation: FloatArray, start_rotation: FloatArray, direction: FloatArray, lateral: FloatArray
) -> tuple[FloatArray, float]:
    """Where the compliant rotations have tipped the part: the lateral direction of the hole.

    A flat-ended part pressed on the hole's mouth with its rotations compliant tips its low rim
    into the mouth: the insertion axis ``n`` it carries turns toward the hole. ``e = R R0^T n - n``
    is that turn's lateral part (``R0`` the orientation the INSERT started with, ``R`` now); the
    hole lies along ``-U U^T e`` (in the searches of tests/run/search_grid.py that direction and
    the tip's bearing to the hole's axis agree within a few degrees once the tilt passes 2 deg).

    Args:
        rotation: R, tool to world. # (3, 3)
        start_rotation: R0, tool to world. # (3, 3)
        direction: n, the insertion direction, world. # (3,)
        lateral: U, the two lateral directions, world (columns). # (3, 2)

    Returns:
        ``(d, |U^T e|)``: the unit direction toward the hole, world (zero when the part is not
        tipped), and the tilt's size (its sine). # (3,)
    """
    n = np.asarray(direction, dtype=float)
    turned = np.asarray(rotation).dot(np.asarray(start_rotation).T.dot(n)) - n
    across = np.asarray(lateral).T.dot(turned)
    size = float(np.linalg.norm(across))
    if size == 0.0:
        return np.zeros(3), 0.0
    return -np.asarray(lateral).dot(across) / size, size


def into_the_hole(
    moved: FloatArray, toward: FloatArray, direction: FloatArray, across_counts: bool = True
) -> float:
    """How far a found part led toward the hole has gone into it: across toward it, plus deeper.

    After a find with the part tipped on the mouth's edge, the lead pushes it across toward the
    hole (``d`` of :func:`toward_the_hole`) until it drops in: both its travel along ``d`` and
    along the insertion direction ``n`` take it in, ``moved . d + moved . n``. Across stops
    counting where the search's own bound says the hole cannot be (``across_counts`` False).

    Args:
        moved: The tool point's displacement since the find, world, [m]. # (3,)
        toward: d, the unit direction toward the hole at the find, world. # (3,)
        direction: n, the insertion direction, world. # (3,)
        across_counts: Whether the travel across counts (False: only the depth does).

    Returns:
        The way made into the hole, in [m] (negative: out of it).
    """
    deeper = float(np.dot(moved, direction))
    return deeper + float(np.dot(moved, toward)) if across_counts else deeper
