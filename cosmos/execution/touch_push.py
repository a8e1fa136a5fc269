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

import numpy as np
from numba.core import types

from cosmos.execution.listing import STATE, VELOCITY, WRENCH, listed
from cosmos.jit import kernel

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

KEPT = 64
"""The most recent ticks the windows keep: 5 ms is 6 ticks at the fastest servo (1 kHz)."""

MASS, SPEEDS_FROM, SPEEDS_COUNT, PUSHES_FROM, PUSHES_COUNT, TOTAL, SPEEDS = 0, 1, 2, 3, 4, 5, 6
"""The tool's inertia's state (the head of a judge's array of floats): the mass below the wrist
sensor [kg] (0 for an approach at :data:`FAST_APPROACH_MPS` or slower: its touch is the push
itself, tick by tick); where the recent speeds ``(t [s], n^T v [m/s])`` start in their ring of
:data:`KEPT` and how many (within :data:`ACCELERATION_WINDOW_S`, oldest first); the same of the
pushes ``(t [s], c [N])`` within :data:`TOUCH_PERSIST_S`, and their sum ``c`` [N]; then the rings."""
PUSHES = SPEEDS + 2 * KEPT
INERTIA_SIZE = PUSHES + 2 * KEPT


def inertia(mass_kg: float, speed_mps: float | None) -> FloatArray:
    """The inertia's state of an approach at SPEED ``speed_mps`` [m/s] whose tool weighs ``mass_kg`` [kg]."""
    state = np.zeros(INERTIA_SIZE)
    state[MASS] = mass_kg if speed_mps is not None and speed_mps > FAST_APPROACH_MPS else 0.0
    return state


@kernel
def _kept(state: FloatArray, ring: int, count_at: int, t_s: float, value: float) -> None:
    """Keep ``(t_s, value)`` as the newest of ``ring``'s (its start at ``count_at - 1``)."""
    count = int(state[count_at])
    if count >= KEPT:
        raise ValueError("a touch window keeps more ticks than it holds")
    at = ring + 2 * ((int(state[count_at - 1]) + count) % KEPT)
    state[at], state[at + 1] = t_s, value
    state[count_at] = count + 1


@kernel
def _oldest(state: FloatArray, ring: int, count_at: int, index: int) -> int:
    """Where the ``index``-th oldest of ``ring``'s entries is."""
    return ring + 2 * ((int(state[count_at - 1]) + index) % KEPT)


@kernel
def _drop_oldest(state: FloatArray, count_at: int) -> None:
    state[count_at - 1] = (state[count_at - 1] + 1.0) % KEPT
    state[count_at] -= 1.0


@kernel
def speed_up(state: FloatArray, speed_mps: float, t_s: float) -> float:
    """``max(a, 0)``: the measured speed-up along the approach [m/s^2], ``a`` its change over the window.

    Args:
        state: The inertia's (:func:`inertia`).
        speed_mps: ``n^T v``, the tool point's measured speed along the approach [m/s].
        t_s: Now [s].
    """
    if not state[MASS] > 0.0:
        return 0.0
    _kept(state, SPEEDS, SPEEDS_COUNT, t_s, speed_mps)
    while (
        state[SPEEDS_COUNT] > 2
        and t_s - state[_oldest(state, SPEEDS, SPEEDS_COUNT, 1)] >= ACCELERATION_WINDOW_S - 1e-9
    ):
        _drop_oldest(state, SPEEDS_COUNT)
    at = _oldest(state, SPEEDS, SPEEDS_COUNT, 0)
    then_s, then_mps = state[at], state[at + 1]
    if not t_s > then_s:
        return 0.0
    a = (speed_mps - then_mps) / (t_s - then_s)
    return 0.0 if 0.0 > a else a  # Python's max(a, 0.0), NaN kept


@kernel
def touched(state: FloatArray, contact_n: float, threshold_n: float, t_s: float) -> bool:
    """Whether the mean of ``contact_n`` [N] over :data:`TOUCH_PERSIST_S` passes ``threshold_n``."""
    if not state[MASS] > 0.0:
        return contact_n > threshold_n
    _kept(state, PUSHES, PUSHES_COUNT, t_s, contact_n)
    state[TOTAL] += contact_n
    while t_s - state[_oldest(state, PUSHES, PUSHES_COUNT, 0)] >= TOUCH_PERSIST_S - 1e-9:
        state[TOTAL] -= state[_oldest(state, PUSHES, PUSHES_COUNT, 0) + 1]
        _drop_oldest(state, PUSHES_COUNT)
    return state[TOTAL] / state[PUSHES_COUNT] > threshold_n


@kernel
def approach_push(
    state: FloatArray, wrench: FloatArray, velocity: FloatArray, direction: FloatArray, t_s: float
) -> tuple[float, float]:
    """``(n^T f_s, c)`` [N]: a CONTACT approach's sensed push along ``n``, and the environment's (``c``).

    ``c = n^T f_s - m max(a, 0)`` (:func:`speed_up`).

    Args:
        state: The inertia's (:func:`inertia`).
        wrench: The sensed wrench on the environment, world [N, N m]. # (6,)
        velocity: The tool's measured twist, world [m/s, rad/s]. # (6,)
        direction: ``n``, the approach's unit direction, world. # (3,)
        t_s: Now [s].
    """
    dx, dy, dz = direction[0], direction[1], direction[2]
    push = wrench[0] * dx + wrench[1] * dy + wrench[2] * dz
    speed = velocity[0] * dx + velocity[1] * dy + velocity[2] * dz
    return push, push - state[MASS] * speed_up(state, speed, t_s)


DIRECTION, THRESHOLD, PUSH = INERTIA_SIZE, INERTIA_SIZE + 3, INERTIA_SIZE + 4
"""An INSERT's touch (after its inertia's state): the approach's direction, world (3), its touch
threshold [N], and the sensed force when it touched [N]."""
INSERT_SIZE = PUSH + 1


def insert_touch(
    mass_kg: float, speed_mps: float | None, direction: tuple[float, ...], threshold_n: float
) -> FloatArray:
    """The state of an INSERT's touch (:func:`insert_touched`)."""
    state = np.zeros(INSERT_SIZE)
    state[:INERTIA_SIZE] = inertia(mass_kg, speed_mps)
    state[DIRECTION : DIRECTION + 3] = direction
    state[THRESHOLD] = threshold_n
    return state


@kernel(types.boolean(types.Array(types.int64, 1, "C"), types.float64))
def insert_touched(table: np.ndarray, t_s: float) -> bool:
    """Whether an INSERT's approach touched: ``|f_s - m max(a, 0) n|`` over its threshold (``|f_s|`` kept).

    ``table`` lists the snapshot's arrays and the state (:class:`cosmos.execution.listing.Listing`,
    :func:`insert_touch`); ``t_s`` is now [s].
    """
    wrench, velocity = listed(table, WRENCH, 6), listed(table, VELOCITY, 6)
    state = listed(table, STATE, INSERT_SIZE)
    dx, dy, dz = state[DIRECTION], state[DIRECTION + 1], state[DIRECTION + 2]
    fx, fy, fz = wrench[0], wrench[1], wrench[2]
    state[PUSH] = math.sqrt(fx * fx + fy * fy + fz * fz)
    inertia_n = state[MASS] * speed_up(state, velocity[0] * dx + velocity[1] * dy + velocity[2] * dz, t_s)
    fx, fy, fz = fx - inertia_n * dx, fy - inertia_n * dy, fz - inertia_n * dz
    return touched(state, math.sqrt(fx * fx + fy * fy + fz * fz), state[THRESHOLD], t_s)
