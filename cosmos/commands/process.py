"""What the ``cosmos`` command does in its own process that a library caller's process keeps as it is.

A ``cosmos`` process (the console script, ``python -m cosmos``) is the command and
nothing else, start to exit; a caller that imports :mod:`cosmos` or invokes the command
in process (a test, a notebook) keeps its own settings. What the command's process
changes, each for the time it saves a warm ``cosmos run`` (README, "start-up"):

* :func:`one_blas_thread` (when this module is imported, in the command's process:
  :mod:`cosmos.cli` imports it before numpy): numpy's BLAS loads with one thread. OpenBLAS starts a thread
  per core, each with its own buffers, when numpy is first imported (40-50 ms of a
  2-core machine's start-up, more with more cores); cosmos multiplies matrices of at
  most 7 x 7, which OpenBLAS never splits between threads.
* :func:`cosmos.commands.dataclass_code.install` (with the first): the methods ``@dataclass``
  writes for each class are compiled once and kept in the user cache (60 ms).
* :func:`mujoco_without_gl`: MuJoCo is imported without its OpenGL backends (GLFW,
  EGL: 20-40 ms): ``cosmos run`` never renders (``cosmos replay --view/--video`` does,
  and is left alone).
* :func:`numba_alone`: numba is imported without the packages its import only looks at:
  SciPy, for a check of its version (cosmos requires a newer one itself), and PyYAML, for a
  ``.numba_config.yaml`` in the working directory (kept where there is one): 20-40 ms,
  where they are installed (PyYAML comes with Dask, for one).
* :func:`end_process`: the command ends without tearing the interpreter down (freeing
  every module's objects: 30-80 ms); what exit handlers there are still run.

Each applies only before its library is first imported (or, for the last, in the
command's own process) and leaves an environment variable the user set as it was.
"""

from __future__ import annotations

import atexit
import os
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import NoReturn

BLAS_THREADS = "OPENBLAS_NUM_THREADS"
GL_BACKEND = "MUJOCO_GL"


def is_the_command() -> bool:
    """Whether this process was started as ``cosmos`` (the console script or ``python -m cosmos``)."""
    main = sys.modules.get("__main__")
    spec = getattr(main, "__spec__", None)
    if spec is not None:
        return bool(spec.name == "cosmos.__main__")
    return Path(getattr(main, "__file__", "") or "").stem == "cosmos"


_SET_HERE: list[str] = []
"""The environment variables :func:`one_blas_thread` set (and :func:`forget_blas_threads` removes)."""


def one_blas_thread() -> None:
    """Load numpy's BLAS with one thread, if numpy is not imported yet and the user chose no number."""
    if "numpy" not in sys.modules and BLAS_THREADS not in os.environ:
        os.environ[BLAS_THREADS] = "1"
        _SET_HERE.append(BLAS_THREADS)


def forget_blas_threads() -> None:
    """With numpy loaded, the processes the command starts choose their own BLAS threads again."""
    if "numpy" in sys.modules:
        while _SET_HERE:
            os.environ.pop(_SET_HERE.pop(), None)


@contextmanager
def mujoco_without_gl() -> Iterator[None]:
    """Within: MuJoCo, if first imported here, is imported without its OpenGL backends.

    MuJoCo reads ``MUJOCO_GL`` once, at its first import; the variable is as it was
    afterwards, for any process the command starts.
    """
    if "mujoco" in sys.modules:
        yield
        return
    before = os.environ.get(GL_BACKEND)
    os.environ[GL_BACKEND] = "disable"
    try:
        yield
    finally:
        if before is None:
            os.environ.pop(GL_BACKEND, None)
        else:
            os.environ[GL_BACKEND] = before


NUMBA_GLANCES_AT = ("scipy", "yaml")
"""What numba's import looks at and nothing else does before it: SciPy (``numba/__init__.py`` checks
its version) and PyYAML (``numba.core.config`` reads ``.numba_config.yaml`` with it, if there is one)."""
NUMBA_CONFIG_FILE = ".numba_config.yaml"


def numba_alone() -> None:
    """Import numba, if it is not imported yet, without the packages it only glances at.

    Each of :data:`NUMBA_GLANCES_AT` not imported yet looks missing to numba's import (as if
    not installed, which numba allows), and is importable again afterwards, by the first
    that needs it (numba's linear algebra imports SciPy's when it compiles). PyYAML stays
    visible where numba would read a configuration file with it.
    """
    if "numba" in sys.modules:
        return
    hidden = [name for name in NUMBA_GLANCES_AT if name not in sys.modules]
    if os.path.isfile(NUMBA_CONFIG_FILE) and "yaml" in hidden:
        hidden.remove("yaml")
    for name in hidden:
        sys.modules[name] = None  # type: ignore[assignment]  # import raises ImportError
    try:
        import numba  # noqa: F401
    finally:
        for name in hidden:
            if name in sys.modules and sys.modules[name] is None:
                del sys.modules[name]


def end_process(code: str | int | None) -> NoReturn:
    """End the command's process with ``code`` (as :func:`sys.exit` takes it), skipping the teardown.

    The exit handlers run (the first run's compile summary, the run log's last resort close),
    stdout and stderr are flushed; the modules' objects are left to the operating system. With
    another thread still running (one that is not a daemon), or if a flush fails, the
    interpreter exits as usual.
    """
    main = threading.main_thread()
    if any(t is not main and t.is_alive() and not t.daemon for t in threading.enumerate()):
        sys.exit(code)
    atexit._run_exitfuncs()
    if code is None:
        status = 0
    elif isinstance(code, int):
        status = code
    else:
        print(code, file=sys.stderr)
        status = 1
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        sys.exit(code)
    os._exit(status)


if is_the_command():
    one_blas_thread()
    from cosmos.commands import dataclass_code  # imports numpy: after one_blas_thread

    dataclass_code.install()
