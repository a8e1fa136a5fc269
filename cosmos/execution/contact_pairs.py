"""MuJoCo's contacts' geom pairs as the protective stops' compiled tick reads them: views that last.

MuJoCo writes its contacts at the start of its arena every step: the view of their geom pairs
(``data.contact.geom``, whose list the bindings build on every call, 0.5-1 us) is kept while
their count stays the same, and made again when it changes
(:mod:`cosmos.execution.supervision`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.lib.stride_tricks import as_strided

from cosmos.execution.supervision_kernel import GEOMS

IntArray = np.ndarray

_NONE = np.zeros((2, 4), dtype=np.int32)[:, ::2]
"""No contacts' geom pairs, as a strided view."""


class ContactPairs:
    """The geom pairs of MuJoCo's contacts now, as views, and their entry in the compiled tick's table.

    Args:
        data: MuJoCo's data (its contacts).
        table: The tick's table (:func:`cosmos.execution.supervision_kernel.supervise_listed`):
            its ``GEOMS`` entry is written whenever the count changes. # (TABLE_SIZE,) int64
    """

    __slots__ = ("_data", "_table", "count", "kernel_view", "view")

    def __init__(self, data: Any, table: IntArray):
        self._data, self._table = data, table
        self.count = 0
        """How many contacts :attr:`view` has (the count it was made for)."""
        self.view: IntArray = _NONE[:0]
        """The contacts' geom pairs, a live view. # (count, 2)"""
        self.kernel_view: IntArray = _NONE
        """The same for :func:`~cosmos.execution.supervision_kernel.supervise_tick`: always strided."""

    def update(self, ncon: int) -> IntArray:
        """The view of MuJoCo's ``ncon`` geom pairs, made again if their count changed. # (ncon, 2)."""
        if ncon == self.count:
            return self.view
        view = self.view = self._data.contact.geom
        self.count = ncon
        # For the compiled tick, always a strided view (numba types one or no contact's as contiguous,
        # and converts in Python, 1 us a call): two rows of the contacts' memory, or none's.
        self.kernel_view = view if ncon > 1 else as_strided(view, (2, 2), view.strides) if ncon else _NONE
        # The listed tick reads the pairs as the first two int32 of each contact's record.
        record = max(2, view.strides[0] // view.itemsize) if ncon else 2
        self._table[GEOMS : GEOMS + 3] = (view.ctypes.data if ncon else 0, ncon, record)
        return view
