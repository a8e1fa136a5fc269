"""Small dense products in plain loops, compiled (numba): the kernels' linear algebra.

For 6 x 6 operands a BLAS call from compiled code costs more than the product;
these are ``@`` written out. ``tests/runtime/test_linear_kernel.py`` checks them
against NumPy's products.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray


@kernel
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


@kernel
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


@kernel
def max_abs_product(matrix: FloatArray, vector: FloatArray) -> float:
    """``max |matrix @ vector|`` without the product's array."""
    largest = 0.0
    for i in range(matrix.shape[0]):
        acc = 0.0
        for k in range(matrix.shape[1]):
            acc += matrix[i, k] * vector[k]
        largest = max(largest, abs(acc))
    return largest


@kernel
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
