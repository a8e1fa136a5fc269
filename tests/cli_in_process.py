"""The ``cosmos`` command line called in this process, for tests of what a command prints.

A test whose subject is a command's exit status, stdout and stderr (usage errors, a summary,
a refused file) runs it through :func:`cosmos.cli.main`, the console script's own entry point,
which renders cosmos's errors as the console script does; only the interpreter's start-up
(0.5-1 s of CPU a command) is left out. Tests whose subject is the process itself (start-up,
imports, signals, exit handlers, a fresh process's caches) start ``python -m cosmos``.
"""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys

from tests.runlog.cli_support import hang_guard


def cosmos_in_process(*args: str, timeout: float = 120.0) -> subprocess.CompletedProcess[str]:
    """``cosmos ARGS`` in this process: exit status, stdout and stderr as a subprocess gives them.

    An exception that escapes :func:`cosmos.cli.main` (what a user would see as a traceback)
    is raised here, failing the test, and so is a command still running after ``timeout`` [s]
    (the bound the tests' subprocesses had).
    """
    out, err = io.StringIO(), io.StringIO()
    argv, sys.argv = sys.argv, ["cosmos", *args]
    status: int
    try:
        with hang_guard(timeout), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            from cosmos.cli import main

            main()
        status = 0
    except SystemExit as done:
        if done.code is None or isinstance(done.code, int):
            status = done.code or 0
        else:  # sys.exit("message"): the message on stderr, status 1, as the interpreter does
            err.write(f"{done.code}\n")
            status = 1
    finally:
        sys.argv = argv
    return subprocess.CompletedProcess(["cosmos", *args], status, out.getvalue(), err.getvalue())
