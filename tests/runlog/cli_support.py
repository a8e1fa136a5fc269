"""The command line in this process, and a guard that turns a hang into a failure."""

from __future__ import annotations

import signal
import sys
from collections.abc import Iterator
from contextlib import contextmanager

import pytest

from cosmos.cli import main

HANG_S = 20  # far beyond any of the reads and refusals tested (each well under a second)
RUN_HANG_S = 300  # a first run compiles the controller's kernels (about 30 s of CPU) on a cold cache


@contextmanager
def hang_guard(seconds: float = HANG_S) -> Iterator[None]:
    """Fail (instead of waiting for ever) if the block runs longer than ``seconds``."""

    def expire(signum: int, frame: object) -> None:
        raise TimeoutError(f"still running after {seconds} s: a hang")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def cli(
    argv: list[str], capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> tuple[int, str, str]:
    """``cosmos ARGV`` in this process: exit status, stdout, stderr."""
    monkeypatch.setattr(sys, "argv", ["cosmos", *argv])
    with hang_guard(RUN_HANG_S if argv[0] == "run" else HANG_S), pytest.raises(SystemExit) as exit_status:
        main()
    out, err = capsys.readouterr()
    code = exit_status.value.code
    return (code if isinstance(code, int) else 1), out, err
