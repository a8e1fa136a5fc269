"""Small dense products in plain loops, compiled (numba): the kernels' linear algebra.

For 6 x 6 operands a BLAS call from compiled code costs more than the product;
these are ``@`` written out. ``tests/runtime/test_linear_kernel.py`` checks them
against NumPy's products.

Each has one signature, compiled once: operands of any layout (a transpose, a
column, a row of a block), read-only or not, so that no caller's arguments
compile another copy of it (numba compiles a kernel again for every new
combination of layouts, writability and literal arguments it is called with).
The ``*_into`` kernels copy into a slice of a larger array, which numba's slice
assignment would do at the cost of compiling its shape-mismatch error message.
"""

from __future__ import annotations

import numpy as np
from numba.core import types

from cosmos.jit import kernel

FloatArray = np.ndarray

MATRIX = types.Array(types.float64, 2, "A", readonly=True)
"""An operand matrix: any layout, read-only or not (a writable array converts to it)."""
VECTOR = types.Array(types.float64, 1, "A", readonly=True)
"""An operand vector: any layout, read-only or not."""
OUT_MATRIX = types.Array(types.float64, 2, "A")
"""A matrix written into: any layout (a block of a larger array)."""
OUT_VECTOR = types.Array(types.float64, 1, "A")
"""A vector written into: any layout (a column of a matrix, a slice)."""
NEW_MATRIX = types.Array(types.float64, 2, "C")
NEW_VECTOR = types.Array(types.float64, 1, "C")


@kernel(NEW_VECTOR(MATRIX, VECTOR))
def matvec(matrix: FloatArray, vector: FloatArray) -> FloatArray:
    """``matrix @ vector`` in plain loops (BLAS costs more than the product at this size)."""
    rows, cols = matrix.shape
    out = np.zeros(rows)
    for i in range(rows):
        acc = 0.0
        for k in range(cols):
            acc += matrix[i, k] * vector[k]
        out[i] = acc
    return out


@kernel(NEW_MATRIX(MATRIX, MATRIX))
def matmul(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a @ b`` in plain loops: for 6 x 6 operands cheaper than a BLAS call from compiled code."""
    n, m, p = a.shape[0], a.shape[1], b.shape[1]
    out = np.zeros((n, p))
    for i in range(n):
        for k in range(m):
            aik = a[i, k]
            for j in range(p):
                out[i, j] += aik * b[k, j]
    return out


@kernel(types.float64(MATRIX, VECTOR))
def max_abs_product(matrix: FloatArray, vector: FloatArray) -> float:
    """``max |matrix @ vector|`` without the product's array."""
    largest = 0.0
    for i in range(matrix.shape[0]):
        acc = 0.0
        for k in range(matrix.shape[1]):
            acc += matrix[i, k] * vector[k]
        largest = max(largest, abs(acc))
    return largest


@kernel(NEW_VECTOR(MATRIX, VECTOR, types.boolean))
def rotate_blocks(rotation: FloatArray, vector: FloatArray, transpose: bool) -> FloatArray:
    """``(R v[:3], R v[3:])``, or with R^T. # (6,)."""
    out = np.empty(6)
    for block in range(2):
        o = 3 * block
        for i in range(3):
            acc = 0.0
            for k in range(3):
                acc += (rotation[k, i] if transpose else rotation[i, k]) * vector[o + k]
            out[o + i] = acc
    return out


@kernel(types.void(OUT_VECTOR, VECTOR, types.float64))
def scaled_into(out: FloatArray, vector: FloatArray, factor: float) -> None:
    """``out[:] = factor * vector`` (``out`` and ``vector`` of one length)."""
    for i in range(out.shape[0]):
        out[i] = factor * vector[i]


@kernel(types.void(OUT_MATRIX, MATRIX, types.float64))
def scaled_matrix_into(out: FloatArray, matrix: FloatArray, factor: float) -> None:
    """``out[:, :] = factor * matrix`` (``out`` and ``matrix`` of one shape)."""
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = factor * matrix[i, j]
