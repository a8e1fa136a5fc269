"""Array type aliases shared by the operational-space maths."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
"""A float64 array; its shape is stated where it is used, e.g. ``# (6, nv)``."""

BoolArray = npt.NDArray[np.bool_]
"""A boolean array; its shape is stated where it is used."""
