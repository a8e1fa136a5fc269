"""A status line while the arm moves: the statement, its simulated time, the real-time factor."""

from __future__ import annotations

import time
from types import TracebackType

from rich.console import Console

from cosmos.execution.executor import Progress


class StatementProgress:
    """Shows one statement's progress on stderr (a rich status line) while inside ``with``.

    Args:
        start_s: Simulated time when the statement starts [s]; the line counts from it.
    """

    def __init__(self, start_s: float):
        self.start_s = start_s
        self.started = time.perf_counter()
        self.status = Console(stderr=True).status("starting")

    def __call__(self, progress: Progress) -> None:
        """Show where the statement is."""
        elapsed_s = progress.t_s - self.start_s
        wall_s = time.perf_counter() - self.started
        factor = elapsed_s / wall_s if wall_s > 0 else 0.0
        self.status.update(
            f"line {progress.line}: {progress.statement}   t = {elapsed_s:5.2f} s   "
            f"real-time factor {factor:4.2f}   (Ctrl-C stops the arm)"
        )

    def __enter__(self) -> StatementProgress:
        self.status.start()
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.status.stop()
