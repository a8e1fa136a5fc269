"""What the compiled kernels' tests compare with: exact agreement and random selections."""

from __future__ import annotations

import numpy as np

from cosmos.osc.force import selection
from cosmos.osc.orientation import so3_exp


def close(actual: np.ndarray, expected: np.ndarray) -> None:
    """``actual`` is ``expected`` to rounding (relative 1e-12 of the largest entry)."""
    scale = max(float(np.max(np.abs(expected))), 1e-12)
    np.testing.assert_allclose(actual, expected, rtol=1e-12, atol=1e-12 * scale)


def omega_bar(rng: np.random.Generator) -> np.ndarray:
    """A random selection's Omega_bar in a random task frame. # (6, 6)."""
    axes = tuple(bool(b) for b in rng.integers(0, 2, 6))
    return selection(axes, so3_exp(rng.uniform(-3.0, 3.0, 3))).omega_bar
