"""The kernels' hand-written products (cosmos.runtime.kernels.linear) against NumPy's ``@``."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.orientation import so3_exp
from cosmos.runtime.kernels import linear


@pytest.mark.parametrize("shape", [(6, 6, 6), (3, 6, 2), (6, 3, 6), (1, 1, 1)])
def test_matmul_is_numpys_product(shape: tuple[int, int, int]) -> None:
    """Catches swapped indices (``a^T b``), a dropped inner term or an accumulation across rows."""
    rng = np.random.default_rng(sum(shape))
    n, m, p = shape
    a, b = rng.normal(size=(n, m)), rng.normal(size=(m, p))
    np.testing.assert_allclose(linear.matmul(a, b), a @ b, rtol=1e-13, atol=1e-13)


def test_max_abs_product_is_the_largest_entry_of_the_product() -> None:
    """Catches the signed maximum taken (a large negative entry missed) or the wrong product."""
    rng = np.random.default_rng(5)
    for _ in range(50):
        matrix, vector = rng.normal(size=(6, 6)), rng.normal(size=6)
        assert linear.max_abs_product(matrix, vector) == pytest.approx(
            np.max(np.abs(matrix @ vector)), rel=1e-13
        )
    assert linear.max_abs_product(-np.eye(6), np.full(6, 3.0)) == 3.0


@pytest.mark.parametrize("transpose", [False, True])
def test_rotate_blocks_turns_both_halves(transpose: bool) -> None:
    """``(R v[:3], R v[3:])`` (or with R^T): catches one half left unturned or R and R^T confused."""
    rng = np.random.default_rng(9)
    rotation = np.zeros((6, 6))
    rotation[:3, :3] = so3_exp(rng.uniform(-3.0, 3.0, 3))
    r = rotation[:3, :3].T if transpose else rotation[:3, :3]
    vector = rng.normal(size=6)
    expected = np.concatenate((r @ vector[:3], r @ vector[3:]))
    np.testing.assert_allclose(linear.rotate_blocks(rotation, vector, transpose), expected, atol=1e-14)


def test_one_signature_takes_transposes_columns_and_read_only_operands() -> None:
    """Each product has one compiled signature (any layout, read-only or not): catches a signature
    narrowed to contiguous or writable operands, which rejects a transpose, a column or a plan's
    read-only array (or, without the explicit signature, compiles the kernel again for each)."""
    rng = np.random.default_rng(3)
    a, block = rng.normal(size=(6, 6)), rng.normal(size=(6, 8))
    frozen = a.copy()
    frozen.flags.writeable = False
    column = block[:, 2]
    np.testing.assert_allclose(linear.matmul(a.T, frozen), a.T @ a, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(linear.matvec(frozen.T, column), a.T @ column, rtol=1e-13, atol=1e-13)
    largest = np.max(np.abs(block[:, :6] @ column))
    assert linear.max_abs_product(block[:, :6], column) == pytest.approx(largest)
    out = np.zeros((8, 6))
    linear.scaled_matrix_into(out[1:7, :], frozen.T, -2.0)
    np.testing.assert_array_equal(out[1:7], -2.0 * a.T)
    linear.scaled_into(out[:, 3], block[2, :], 0.5)
    np.testing.assert_array_equal(out[:, 3], 0.5 * block[2])
    for kernel in (linear.matmul, linear.matvec, linear.max_abs_product, linear.rotate_blocks):
        assert len(kernel.signatures) == 1, kernel
