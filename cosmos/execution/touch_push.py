"""A CONTACT's touch is a push the environment makes, not the tool's own inertia.

The wrist sensor hangs the tool below it: its weight is compensated
(:mod:`cosmos.runtime.wrench`), its acceleration is not, so a tool of mass ``m`` speeding up
along the approach at ``a`` reads ``m a`` along it as a push. An approach at SPEED 100 mm/s
speeds up at some 3 m/s^2: the peg (0.66 kg) read 2.11 N 21 ms after the CONTACT began, in free
air, more than the 2 N touch threshold, and the hold then pushed the tool 606 mm through free
space (issue 14). So the touch is judged on

    c = n^T f_s - m max(n^T a, 0)

with ``a`` the tool point's measured acceleration along the approach ``n`` (the encoders'
``J qd`` over :data:`ACCELERATION_WINDOW_S`). Only speeding up is taken out: a tool slowed by
the surface reads less than the surface's push, never more, so a real touch is never delayed.
The encoders' speed lags the sensor by some 5 ms (the observer's filter), and so it is ``c``'s
mean over the last :data:`TOUCH_PERSIST_S` (the lag, the window) that must pass the threshold: a
speed-up's first milliseconds, read before the speed shows them, are not a touch, and neither is
a spike of the wrist's ringing (3 N for a tick, SPEED 100 mm/s along +Y). A landing on the
table rings at 500 Hz (2.0, -0.1, 3.5, 0.1, 3.0 N tick by tick): a touch that every tick of the
window had to pass came 25 ms late, at 4.8 N for a 3 N CONTACT; the mean passes 4 ms late.

Only an approach whose SPEED is over :data:`FAST_APPROACH_MPS` is judged so: slower, its speed-up
reads under 0.2 N (docs/language.md, UNTIL), and its touch is the sensed push over the threshold,
tick by tick, as every landing grid measured it (a touch a few milliseconds later changes a
realistic run's whole path: INSERT SPEED 5 mm/s, seed 1, then peaked at 6.1 mm/s 4.6 s later,
5.3 before).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np

FloatArray = np.ndarray

FAST_APPROACH_MPS = 0.030
"""An approach whose SPEED is over this [m/s] has its touch judged without the tool's inertia: the
fastest landing the grids measured under the bar (cosmos.osc.landing.CUSHIONED_LANDING_MPS)."""

ACCELERATION_WINDOW_S = 0.005
"""The measured acceleration is the speed's change over this [s]: one encoder count's speed
noise (1-3 mm/s on the realistic plant) reads 0.2-0.6 m/s^2 over it, 0.1-0.4 N on the peg."""

TOUCH_PERSIST_S = 0.005
"""The touch is judged on the contact's push averaged over this [s]: the observer's lag behind the
sensor (at SPEED 100 mm/s the peg read 1.17 N of speed-up at 0.986 s, before the measured speed
rose; a steel landing's push rises for 5-7 ms to its peak, so the touch is no later than that)."""


@dataclass(slots=True)
class ToolInertia:
    """The approach's recent speeds (:data:`ACCELERATION_WINDOW_S`) and pushes (:data:`TOUCH_PERSIST_S`).

    Attributes:
        mass_kg: The mass below the wrist sensor [kg]; 0 for an approach at :data:`FAST_APPROACH_MPS`
            or slower: its touch is the push itself, tick by tick.
        speeds: ``(t [s], n^T v [m/s])`` of the recent ticks, oldest first.
        pushes: ``(t [s], c [N])`` of the ticks within :data:`TOUCH_PERSIST_S`, oldest first.
        total_n: The sum of :attr:`pushes`' ``c`` [N].
    """

    mass_kg: float
    speeds: deque[tuple[float, float]] = field(default_factory=deque)
    pushes: deque[tuple[float, float]] = field(default_factory=deque)
    total_n: float = 0.0

    @classmethod
    def of(cls, mass_kg: float, speed_mps: float | None) -> ToolInertia:
        """The judge of an approach at SPEED ``speed_mps`` [m/s] whose tool weighs ``mass_kg`` [kg]."""
        return cls(mass_kg if speed_mps is not None and speed_mps > FAST_APPROACH_MPS else 0.0)

    def speed_up(self, speed_mps: float, t_s: float) -> float:
        """``max(a, 0)``: the measured speed-up along the approach [m/s^2], ``a`` its change over the window.

        Args:
            speed_mps: ``n^T v``, the tool point's measured speed along the approach [m/s].
            t_s: Now [s].
        """
        if not self.mass_kg > 0.0:
            return 0.0
        speeds = self.speeds
        speeds.append((t_s, speed_mps))
        while len(speeds) > 2 and t_s - speeds[1][0] >= ACCELERATION_WINDOW_S - 1e-9:
            speeds.popleft()
        then_s, then_mps = speeds[0]
        return max((speed_mps - then_mps) / (t_s - then_s), 0.0) if t_s > then_s else 0.0

    def contact_push(self, push_n: float, speed_mps: float, t_s: float) -> float:
        """``c = n^T f_s - m max(a, 0)`` [N] (:meth:`speed_up`); ``push_n`` is ``n^T f_s`` [N]."""
        return push_n - self.mass_kg * self.speed_up(speed_mps, t_s)

    def approach_push(
        self, wrench: FloatArray, velocity: FloatArray, direction: tuple[float, ...], t_s: float
    ) -> tuple[float, float]:
        """``(n^T f_s, c)`` [N]: a CONTACT approach's sensed push along ``n``, and the environment's (``c``).

        Args:
            wrench: The sensed wrench on the environment, world [N, N m]. # (6,)
            velocity: The tool's measured twist, world [m/s, rad/s]. # (6,)
            direction: ``n``, the approach's unit direction, world. # (3,)
            t_s: Now [s].
        """
        (dx, dy, dz), (fx, fy, fz, _, _, _) = direction, wrench.tolist()
        vx, vy, vz, _, _, _ = velocity.tolist()
        push = fx * dx + fy * dy + fz * dz
        return push, self.contact_push(push, vx * dx + vy * dy + vz * dz, t_s)

    def insert_push(
        self, wrench: FloatArray, velocity: FloatArray, direction: tuple[float, ...], t_s: float
    ) -> tuple[float, float]:
        """``(|f_s|, |f_s - m max(a, 0) n|)`` [N]: an INSERT approach's sensed force, and the environment's.

        Arguments as :meth:`approach_push`'s.
        """
        (dx, dy, dz), (fx, fy, fz, _, _, _) = direction, wrench.tolist()
        vx, vy, vz, _, _, _ = velocity.tolist()
        push = math.sqrt(fx * fx + fy * fy + fz * fz)
        inertia = self.mass_kg * self.speed_up(vx * dx + vy * dy + vz * dz, t_s)
        fx, fy, fz = fx - inertia * dx, fy - inertia * dy, fz - inertia * dz
        return push, math.sqrt(fx * fx + fy * fy + fz * fz)

    def touched(self, contact_n: float, threshold_n: float, t_s: float) -> bool:
        """Whether the mean of ``contact_n`` [N] over :data:`TOUCH_PERSIST_S` passes ``threshold_n``."""
        if not self.mass_kg > 0.0:
            return contact_n > threshold_n
        pushes = self.pushes
        pushes.append((t_s, contact_n))
        self.total_n += contact_n
        while t_s - pushes[0][0] >= TOUCH_PERSIST_S - 1e-9:
            self.total_n -= pushes.popleft()[1]
        return self.total_n / len(pushes) > threshold_n
