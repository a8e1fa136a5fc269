"""Arrays handed to a kernel by address: one int64 table instead of a dozen array arguments (numba).

numba's dispatcher converts every array argument of a call from Python (its type
looked up, a view made for the compiled code, released after): about 50 ns each
on the 2-core target, so a kernel of twelve arrays called every servo tick spends
more in its call than in its work. :class:`ArrayTable` lists arrays that outlive
their kernels' calls (MuJoCo's own, which it never moves, and buffers allocated
once) by address and shape in an int64 table, and the kernel makes its views from
that table (:func:`float_rows`, :func:`int32_rows`, :func:`int64_rows`; a vector is
listed as a matrix of one row, its view is that row) at the cost of a few loads each.

The table holds the arrays themselves, so they live as long as it does; an array
must be C-contiguous and of the dtype its view is made with (checked when it is
listed).
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

from cosmos.jit import kernel

ENTRY = 3  # per array: its address, rows, columns (a vector is one row)


def _as_pointer(typingctx: object, address: types.Type) -> tuple[Any, Any] | None:
    """The integer ``address`` as a ``void *`` (for ``numba.carray``)."""
    if not isinstance(address, types.Integer):
        return None

    def codegen(context: object, builder: ir.IRBuilder, signature: object, args: list[ir.Value]) -> ir.Value:
        return builder.inttoptr(args[0], cgutils.voidptr_t)

    return types.voidptr(address), codegen


_pointer: Any = intrinsic(_as_pointer)  # called as _pointer(address) in compiled code


@kernel
def float_rows(table: np.ndarray, at: int) -> np.ndarray:
    """The float64 matrix listed at ``table[at:at + ENTRY]``."""
    return numba.carray(_pointer(table[at]), (table[at + 1], table[at + 2]), np.float64)


@kernel
def int32_rows(table: np.ndarray, at: int) -> np.ndarray:
    """The int32 matrix listed at ``table[at:at + ENTRY]``."""
    return numba.carray(_pointer(table[at]), (table[at + 1], table[at + 2]), np.int32)


@kernel
def int64_rows(table: np.ndarray, at: int) -> np.ndarray:
    """The int64 matrix listed at ``table[at:at + ENTRY]``."""
    return numba.carray(_pointer(table[at]), (table[at + 1], table[at + 2]), np.int64)


class ArrayTable:
    """Arrays listed by address, rows and columns for a kernel (:data:`ENTRY` int64 each); holds them.

    Args:
        arrays: The arrays, each with the dtype its kernel's view expects. # (rows,) or (rows, columns)

    Raises:
        ValueError: If an array is not C-contiguous, not 1- or 2-dimensional, or of another dtype
            than float64, int32 or int64.
    """

    def __init__(self, *arrays: np.ndarray) -> None:
        entries: list[int] = []
        for array in arrays:
            if not array.flags.c_contiguous or array.ndim not in (1, 2):
                raise ValueError(f"a table lists C-contiguous vectors and matrices, not {array.shape}")
            if array.dtype not in (np.float64, np.int32, np.int64):
                raise ValueError(f"a table lists float64, int32 and int64 arrays, not {array.dtype}")
            rows, columns = array.shape if array.ndim == 2 else (1, array.shape[0])
            entries += [int(array.ctypes.data), rows, columns]
        self.arrays = arrays
        """The arrays listed (kept alive with the table)."""
        self.entries = np.array(entries, dtype=np.int64)
        """Per array its address, rows and columns. # (ENTRY * len(arrays),)"""
