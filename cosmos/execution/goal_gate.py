"""Whether a goal motion's tick can pass its judge by: the test its judge passed most ticks on.

A goal motion has arrived only with its tool point within its position tolerance of the goal
(on the motion axes) and moving no faster than its speed tolerance
(:meth:`cosmos.execution.monitor.SegmentMonitor._goal_reached`). On every other tick the judge
finds "on its way" and looks no further, but for its whole judgement (orientation, stall,
overrun) every ``EVERY`` ticks counted: that test and that count are compiled here
(:func:`passes`). In Python (an array's ``tolist``, a square root, a loop over the axes, the
judge's call) they cost 0.5-1 us a tick; compiled, a call on the listed arrays
(:func:`passes_listed`) costs about 0.1 us, and the executor's loop calls the judge only on the
ticks it does not pass by. The arithmetic is the one the judge did in Python, in the same order
(no fused products: numba compiles without ``fastmath``).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
from numba.core import types

from cosmos.jit import kernel
from cosmos.obstacles.kernels.arrays import _pointer

FloatArray = np.ndarray

GOAL, SPEED_TOLERANCE, POSITION_TOLERANCE2, AXES_COUNT, EVERY, TICKS, PASSED, AXES = 0, 3, 4, 5, 6, 7, 8, 9
"""The gate's layout (one array of floats): the goal point (3), the speed tolerance [m/s], the
position tolerance squared [m^2], how many motion axes; every how many ticks the judge looks at the
whole error anyway, the ticks counted so far, whether a tick has passed since the judge last looked
(1.0); then the axes as rows of 3 (world)."""
GATE_SIZE = AXES + 9


def gate(
    goal: tuple[float, ...],
    speed_mps: float,
    tolerance_m: float,
    axes: list[tuple[float, ...]],
    every: int,
) -> FloatArray:
    """The gate's array: a goal point, its tolerances, its motion axes, the judge's period. # (GATE_SIZE,)."""
    array = np.zeros(GATE_SIZE)
    array[GOAL : GOAL + 3] = goal
    array[SPEED_TOLERANCE] = speed_mps
    array[POSITION_TOLERANCE2] = tolerance_m * tolerance_m
    array[AXES_COUNT] = len(axes)
    array[EVERY] = every
    for k, row in enumerate(axes):
        array[AXES + 3 * k : AXES + 3 * k + 3] = row
    return array


@kernel
def on_its_way(position: FloatArray, velocity: FloatArray, gate: FloatArray) -> bool:
    """Whether the tool has not arrived at this tick: too fast, or off its goal point.

    Args:
        position: The measured tool point, world [m]. # (3,)
        velocity: The tool's twist ``J qd``, world [m/s, rad/s]. # (6,)
        gate: The goal and its tolerances (:func:`gate`). # (GATE_SIZE,)

    Returns:
        The tool point's speed above the speed tolerance, or its distance from the goal point on
        the motion axes beyond the position tolerance.
    """
    vx, vy, vz = velocity[0], velocity[1], velocity[2]
    if math.sqrt(vx * vx + vy * vy + vz * vz) > gate[SPEED_TOLERANCE]:
        return True
    ex = position[0] - gate[GOAL]
    ey = position[1] - gate[GOAL + 1]
    ez = position[2] - gate[GOAL + 2]
    total = 0.0
    for k in range(int(gate[AXES_COUNT])):
        at = AXES + 3 * k
        component = gate[at] * ex + gate[at + 1] * ey + gate[at + 2] * ez
        total += component * component
    return total > gate[POSITION_TOLERANCE2]


@kernel
def passes(position: FloatArray, velocity: FloatArray, gate: FloatArray) -> bool:
    """Count a tick; whether it passes the judge by: not one of every ``EVERY`` and :func:`on_its_way`.

    A tick that passes breaks an arrival's settling: ``gate[PASSED]`` is set (the judge clears it).
    """
    gate[TICKS] += 1.0
    if gate[TICKS] % gate[EVERY] != 0.0 and on_its_way(position, velocity, gate):
        gate[PASSED] = 1.0
        return True
    return False


POSITION, VELOCITY, GATE = 0, 1, 2
"""A listed gate's table (int64): the addresses of the tool point (3), the twist (6) and the gate."""


@kernel(types.boolean(types.Array(types.int64, 1, "C")))
def passes_listed(table: np.ndarray) -> bool:
    """:func:`passes` on the arrays ``table`` lists by address: one array to convert, not three."""
    position = numba.carray(_pointer(table[POSITION]), 3, np.float64)
    velocity = numba.carray(_pointer(table[VELOCITY]), 6, np.float64)
    gate = numba.carray(_pointer(table[GATE]), GATE_SIZE, np.float64)
    return passes(position, velocity, gate)


class GoalGate:
    """A goal's :func:`passes`, called on the live arrays of the snapshot it was last asked about.

    The executor makes one snapshot a segment, of live views (the monitor's ``Snapshot``): its tool
    point and twist are listed once (:meth:`list`, or the first :meth:`passes`), and every tick
    after calls :attr:`listed` on :attr:`table`: ``gate.listed(gate.table) if snap is
    gate.snapshot else gate.passes(snap)``.

    Args:
        goal: The goal point, world [m].
        speed_mps: The speed tolerance [m/s].
        tolerance_m: The position tolerance [m].
        axes: The motion-controlled translation axes, world, one a row.
        every: The judge looks at the whole error every this many ticks, on its way or not.
    """

    __slots__ = ("array", "listed", "snapshot", "table")

    def __init__(
        self,
        goal: tuple[float, ...],
        speed_mps: float,
        tolerance_m: float,
        axes: list[tuple[float, ...]],
        every: int,
    ):
        self.array = gate(goal, speed_mps, tolerance_m, axes, every)
        self.table = np.zeros(3, dtype=np.int64)
        self.table[GATE] = self.array.ctypes.data
        self.snapshot: object = None
        """The snapshot whose tool point and twist :attr:`table` lists (kept alive here)."""
        self.listed = _listed_entry()
        """:func:`passes_listed` without numba's dispatch: ``listed(table)``."""

    def list(self, snap: Any) -> bool:
        """List ``snap``'s tool point and twist (``position``, ``velocity``) if they can be (True)."""
        position, velocity = snap.position, snap.velocity
        if not (_listable(position, 3) and _listable(velocity, 6)):
            return False
        self.snapshot = snap
        self.table[POSITION], self.table[VELOCITY] = position.ctypes.data, velocity.ctypes.data
        return True

    def passes(self, snap: Any) -> bool:
        """:func:`passes` for ``snap``, listed for later ticks if it can be."""
        if self.list(snap):
            return bool(self.listed(self.table))
        return bool(passes(snap.position, snap.velocity, self.array))  # any other layout: numba's dispatch

    def settling_broken(self) -> bool:
        """Whether a tick has passed since the last call (an arrival's settling broken meanwhile)."""
        if not self.array[PASSED]:
            return False
        self.array[PASSED] = 0.0
        return True

    @property
    def ticks(self) -> int:
        """The ticks counted so far."""
        return int(self.array[TICKS])

    @ticks.setter
    def ticks(self, ticks: int) -> None:
        self.array[TICKS] = ticks


def _listable(array: FloatArray, size: int) -> bool:
    """Whether ``array`` can be read at its address as ``size`` float64 in a row."""
    return array.dtype == np.float64 and array.flags.c_contiguous and array.shape == (size,)


_ENTRY: list[Any] = []


def _listed_entry() -> Any:
    """:func:`passes_listed`'s compiled function without numba's dispatch (loaded once)."""
    if not _ENTRY:
        passes_listed.compile_declared()
        (declared,) = passes_listed.signatures
        _ENTRY.append(passes_listed.overloads[declared].entry_point)
    return _ENTRY[0]
