"""Running a compiled plan for ``cosmos run`` and ``cosmos replay --verify``: signals and progress.

:class:`StopOnSignals` is installed before the run log is opened and removed
after it is closed: Ctrl-C and SIGTERM ask the executor to stop the arm (it
holds) while a statement runs, and are ignored while the log is being opened
or closed, so the file always gets its summary and footer and the process its
own exit status.
"""

from __future__ import annotations

import signal
import time
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType, TracebackType
from typing import Any

from cosmos.execution.executor import Executor, Progress
from cosmos.execution.session import Session
from cosmos.plan import Plan
from cosmos.runlog.printable import printable

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class StopOnSignals:
    """Ctrl-C and SIGTERM ask the executor to stop; none ends the process until the log is closed.

    Use as a context around the whole life of a :class:`Session`; call
    :meth:`attach` once its executor exists. A signal that comes before then
    stops the run as soon as it starts.
    """

    def __init__(self) -> None:
        self.executor: Executor | None = None
        self.received = 0
        self._previous: dict[int, Any] = {}

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        self.received += 1
        if self.executor is not None:
            self.executor.stop_requested = True

    def attach(self, executor: Executor) -> None:
        """Send later signals (and one received already) to ``executor``."""
        self.executor = executor
        if self.received:
            executor.stop_requested = True

    def __enter__(self) -> StopOnSignals:
        self._previous = {sig: signal.signal(sig, self._handle) for sig in STOP_SIGNALS}
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)


@contextmanager
def stop_on_signals(executor: Executor) -> Iterator[None]:
    """:class:`StopOnSignals` for an executor that exists already (``cosmos.run`` in Python)."""
    with StopOnSignals() as signals:
        signals.attach(executor)
        yield


class TerminalProgress:
    """One status line on a terminal: statement, simulated time, real-time factor."""

    def __init__(self) -> None:
        from rich.console import Console

        self.console = Console(stderr=True)
        # numba compiles the servo kernels on first use, then caches them.
        self.status = self.console.status("starting (a first run compiles the controller: up to a minute)")
        self.started = time.perf_counter()

    def __call__(self, progress: Progress) -> None:
        """Show where the run is (the statement as plain text: no markup, no control characters)."""
        from rich.markup import escape

        wall = time.perf_counter() - self.started
        factor = progress.t_s / wall if wall > 0 else 0.0
        statement = escape(printable(progress.statement))
        self.status.update(
            f"line {progress.line}: {statement}   t = {progress.t_s:6.2f} s   real-time factor {factor:4.1f}"
        )


def execute_plan(session: Session, plan: Plan, progress: TerminalProgress | None) -> None:
    """Run ``plan`` on the session's arm, with progress on a terminal if given.

    Raises:
        TaskFailure: A statement failed (the arm holds), or the run was interrupted.
    """
    if progress is None:
        session.executor.run(plan)
    else:
        with progress.status:
            session.executor.run(plan)
