"""The user cache directory of cosmos (compiled kernels, plans, model facts, dataclasses' code).

``$COSMOS_CACHE_DIR`` if set, else the platform's user cache directory:
``$XDG_CACHE_HOME/cosmos`` or ``~/.cache/cosmos`` on Linux, ``~/Library/Caches/cosmos``
on macOS, ``%LOCALAPPDATA%/cosmos/Cache`` on Windows. Imports nothing heavy, so
commands that need no simulator (``cosmos check``) can use it. :func:`package_stamp` names
a cache file after the installed packages its content depends on.
"""

from __future__ import annotations

import importlib.util
import os
import pickle
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

CACHE_ENV = "COSMOS_CACHE_DIR"
"""Environment variable naming the directory cosmos caches in (instead of the user cache)."""


def user_cache_root() -> Path:
    """``$COSMOS_CACHE_DIR``, else the platform's user cache directory for cosmos."""
    chosen = os.environ.get(CACHE_ENV)
    if chosen:
        return Path(chosen).expanduser()
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or str(Path.home() / "AppData" / "Local")
        return Path(base) / "cosmos" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "cosmos"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base).expanduser() / "cosmos"


def package_stamp(package: str) -> str:
    """What tells an installed package's versions apart, for naming cache files.

    Its location and its ``__init__``'s size and modification time (installing, upgrading or
    reinstalling writes it anew); ``"none"`` if it is not installed. Cheaper than asking
    ``importlib.metadata`` for the version (which imports the ``email`` package and scans every
    path entry: 20 ms of a 0.35 s check).
    """
    spec = importlib.util.find_spec(package)
    if spec is None or spec.origin is None:
        return "none"
    stat = os.stat(spec.origin)
    return f"{spec.origin}:{stat.st_size}:{stat.st_mtime_ns}"


def write_whole(path: Path, content: str | bytes) -> None:
    """Write ``content`` (text as UTF-8) to ``path`` whole or not at all (another process may be reading it).

    Raises:
        OSError: If the directory or the file cannot be written.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    data = content.encode("utf-8") if isinstance(content, str) else content
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.replace(temporary, path)
    except OSError:
        Path(temporary).unlink(missing_ok=True)
        raise


def cached_array(values: object, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """``values`` as a read-only float array of ``shape`` (if given): a value read back from a cache.

    Raises:
        ValueError: If a value is not finite or they do not fit ``shape`` (the cache is then
            recomputed, as for any damaged file).
    """
    array = np.array(values, dtype=float)
    if shape is not None:
        array = array.reshape(shape)
    if not np.all(np.isfinite(array)):
        raise ValueError("a value that is not finite")
    array.setflags(write=False)
    return array


def _array(
    data: bytes, dtype: np.dtype[Any], shape: tuple[int, ...], fortran: bool, writeable: bool
) -> np.ndarray:
    """An array of its own memory rebuilt from its bytes, as writable as it was kept."""
    array = np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran else "C").copy(order="K")
    array.setflags(write=writeable)
    return array


class ArrayPickler(pickle.Pickler):
    """A pickler that keeps each array as writable as it is.

    numba compiles a kernel anew for a writable array where it had a read-only one, and
    numpy's own pickle reads every array back read-only (protocol 5), or every one writable (older ones).
    """

    def reducer_override(self, obj: Any) -> Any:
        """An array (of no Python objects) as its bytes, dtype, shape, order and writability."""
        if type(obj) is np.ndarray and not obj.dtype.hasobject:
            fortran = bool(obj.flags.f_contiguous and not obj.flags.c_contiguous)
            return _array, (obj.tobytes(order="A"), obj.dtype, obj.shape, fortran, bool(obj.flags.writeable))
        return NotImplemented
