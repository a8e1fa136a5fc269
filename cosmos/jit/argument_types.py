"""numba's type of an array argument, without importing ``numpy.ma`` to find that it is not masked.

The first call of each kernel types its arguments in Python (numba's ``typeof``); for an
array numba first checks that it is not a masked array, ``isinstance(val, np.ma.MaskedArray)``,
and ``np.ma`` is a submodule numpy imports when first named: 10-20 ms of a warm ``cosmos
run``, for a module nothing else in it uses. No masked array exists before ``numpy.ma`` is
imported, so :func:`array_type` asks only then; the rest is numba's own function, line for
line (``numba.core.typing.typeof._typeof_ndarray``). Installed for the numba versions
:mod:`cosmos.jit.loading` was checked against (``tests/test_jit_loading.py`` compares the
two), numba's own otherwise.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np
from numba.core import errors, types
from numba.core.typing.typeof import typeof_impl
from numba.np import numpy_support

from cosmos.jit import loading

NUMBA_ARRAY_TYPE = typeof_impl.dispatch(np.ndarray)
"""numba's own typing of an array argument."""


def array_type(val: np.ndarray, c: Any) -> types.Array:
    """The numba type of the array ``val`` (numba's ``_typeof_ndarray``); a masked array is refused."""
    masked = sys.modules.get("numpy.ma")
    if masked is not None and isinstance(val, masked.MaskedArray):
        raise errors.NumbaTypeError("Unsupported array type: numpy.ma.MaskedArray.")
    try:
        dtype = numpy_support.from_dtype(val.dtype)
    except errors.NumbaNotImplementedError:
        raise errors.NumbaValueError(f"Unsupported array dtype: {val.dtype}") from None
    layout = numpy_support.map_layout(val)
    return types.Array(dtype, val.ndim, layout, readonly=not val.flags.writeable)


def install() -> None:
    """Type array arguments with :func:`array_type` (with a numba version it was checked against)."""
    if loading.ENABLED:
        typeof_impl.register(np.ndarray)(array_type)
