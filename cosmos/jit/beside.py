"""A first run's longest kernel compiled in a second process, beside the others.

numba compiles one kernel at a time in a process. On a first run (an empty
kernel cache) the kernels are needed one after another: the plant's sensing,
the parameter level's evaluation and folding, then the servo tick, which alone
takes about a third of the compile time. A kernel declared with
``@kernel(signature, beside=True)`` is compiled by a helper process started at
the run's first compilation; the helper writes it to the shared kernel cache
while this process compiles the kernels needed before it, and this process,
when it first calls the kernel, waits for the helper and loads it from the
cache (or compiles it itself if the helper failed). On a machine with a second
core free the first run is shorter by the helper's share; with no core free it
is not (at a load average of 5 on 2 cores: 35-41 s wall with a helper, 34-35 s
without, the helper's imports costing 2 s of CPU), so a helper is started only
when the load average leaves a core free. Without a cache directory, or inside a
helper, nothing is started.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from typing import Any

HELPER_ENV = "COSMOS_JIT_HELPER"
"""Set in a helper process: it starts no helper of its own."""
WAIT_S = 300.0
"""Longest wait for a helper before compiling here instead [s]."""

_registered: list[Any] = []
_helpers: dict[int, subprocess.Popen[bytes]] = {}


def register(dispatcher: Any) -> None:
    """Compile ``dispatcher`` (declared signatures, :func:`cosmos.jit.kernel`) beside, on a first run."""
    _registered.append(dispatcher)


def start(directory: object) -> None:
    """Start a helper for each registered kernel this process has not compiled (at its first compilation).

    Args:
        directory: The kernel cache directory (None: no cache to share, nothing is started).
    """
    if directory is None or os.environ.get(HELPER_ENV) or not core_free():
        return
    for dispatcher in _registered:
        if dispatcher.signatures or id(dispatcher) in _helpers or _cached(dispatcher):
            continue
        target = f"{dispatcher.py_func.__module__}:{dispatcher.py_func.__name__}"
        try:
            _helpers[id(dispatcher)] = subprocess.Popen(
                [sys.executable, "-m", "cosmos.jit.beside", target],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                env=dict(os.environ, **{HELPER_ENV: "1"}),
            )
        except OSError:  # no process to be had: this one compiles it
            continue


def core_free() -> bool:
    """Whether a core is free for a helper: more cores than the load average (of the last minute) uses."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    try:
        load = os.getloadavg()[0]
    except OSError:  # not known: assume busy
        return False
    return cores >= 2 and load <= cores - 1


def _cached(dispatcher: Any) -> bool:
    """Whether the kernel cache has an index for ``dispatcher`` (it was compiled there before)."""
    index = getattr(getattr(getattr(dispatcher, "_cache", None), "_cache_file", None), "_index_path", None)
    return index is not None and os.path.exists(index)


def started() -> int:
    """Helpers started and not yet waited for."""
    return len(_helpers)


def wait_for(dispatcher: Any) -> None:
    """Wait until the helper compiling ``dispatcher`` (if any) is done."""
    helper = _helpers.pop(id(dispatcher), None)
    if helper is None:
        return
    try:
        helper.wait(timeout=WAIT_S)
    except subprocess.TimeoutExpired:
        helper.kill()
        helper.wait()


def main(target: str) -> int:
    """In the helper: compile ``module:name``'s declared signatures into the kernel cache."""
    module, name = target.split(":")
    dispatcher = getattr(importlib.import_module(module), name)
    dispatcher.compile_declared()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
