"""A segment judge's arrays listed by address for a compiled call: one int64 array to convert a tick.

The executor makes one snapshot a segment, of live views (:class:`~cosmos.execution.snapshot.Snapshot`:
the tool point, its twist, the wrist's wrench, rewritten in place every tick). A compiled judge
(:mod:`cosmos.execution.approach_stall`, :mod:`cosmos.execution.lost_push`) reads them, and its own
state, at the addresses a :class:`Listing` holds: numba converts one array a call, not four, and is
called without its dispatch (:func:`entry`), some 0.2 us a tick.
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np

from cosmos.jit import kernel
from cosmos.obstacles.kernels.arrays import _pointer

FloatArray = np.ndarray

POSITION, VELOCITY, WRENCH, STATE = 0, 1, 2, 3
"""A listing's table (int64): the addresses of the tool point (3), twist (6), wrench (6), state."""


@kernel
def listed(table: np.ndarray, at: int, size: int) -> FloatArray:
    """The ``size`` float64 listed at ``table[at]``."""
    return numba.carray(_pointer(table[at]), size, np.float64)


class Listing:
    """The arrays of the snapshot a judge was last asked about, and the judge's state, by address.

    Args:
        state: The judge's state (float64, C-contiguous: it is read and written in place).
    """

    __slots__ = ("copies", "snapshot", "state", "table")

    def __init__(self, state: FloatArray):
        self.state = state
        self.table = np.zeros(4, dtype=np.int64)
        self.table[STATE] = state.ctypes.data
        self.snapshot: object = None
        """The snapshot whose arrays :attr:`table` lists (kept alive here); None: copied every tick."""
        self.copies = (np.zeros(3), np.zeros(6), np.zeros(6))

    def list(self, snap: Any) -> None:
        """List ``snap``'s tool point, twist and wrench: by address if they can be read so, else copied."""
        arrays = (snap.position, snap.velocity, snap.wrench)
        if all(_listable(array, size) for array, size in zip(arrays, (3, 6, 6), strict=True)):
            self.snapshot = snap
        else:  # any other layout: copied into arrays that can be, at every call
            self.snapshot = None
            for copy, array in zip(self.copies, arrays, strict=True):
                copy[:] = np.asarray(array, dtype=float).reshape(-1)
            arrays = self.copies
        for at, array in zip((POSITION, VELOCITY, WRENCH), arrays, strict=True):
            self.table[at] = array.ctypes.data


def _listable(array: FloatArray, size: int) -> bool:
    """Whether ``array`` can be read at its address as ``size`` float64 in a row."""
    return (
        isinstance(array, np.ndarray)
        and array.dtype == np.float64
        and array.flags.c_contiguous
        and array.shape == (size,)
    )


_ENTRIES: dict[Any, Any] = {}


def entry(dispatcher: Any) -> Any:
    """``dispatcher``'s one declared compilation without numba's dispatch (compiled or loaded once)."""
    found = _ENTRIES.get(dispatcher)
    if found is None:
        dispatcher.compile_declared()
        (declared,) = dispatcher.signatures
        found = _ENTRIES[dispatcher] = dispatcher.overloads[declared].entry_point
    return found
