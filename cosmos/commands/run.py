"""``cosmos run PROGRAM``: check, compile and run a program on the simulated arm, logged to MCAP."""

from __future__ import annotations

import signal
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from types import FrameType

import click

from cosmos.errors import CosmosError
from cosmos.execution.executor import Executor, Progress
from cosmos.execution.session import Session
from cosmos.lang import compile_program, read_program
from cosmos.plan import Plan
from cosmos.runlog.writer import default_log_path
from cosmos.runtime.rates import Rates
from cosmos.workcell import fixture_frames


def compile_file(path: Path) -> Plan:
    """Parse, check and compile a program file; warnings go to stderr."""
    source = read_program(path)
    plan = compile_program(source, str(path), fixture_frames())
    for warning in plan.warnings:
        click.echo(warning.render(source), err=True)
    return plan


@contextmanager
def stop_on_signals(executor: Executor) -> Iterator[None]:
    """Ctrl-C and SIGTERM ask the executor to stop the arm (it holds) instead of killing the run."""

    def request_stop(signum: int, frame: FrameType | None) -> None:
        executor.stop_requested = True

    previous = {sig: signal.signal(sig, request_stop) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


class TerminalProgress:
    """One status line on a terminal: statement, simulated time, real-time factor."""

    def __init__(self) -> None:
        from rich.console import Console

        self.console = Console(stderr=True)
        # numba compiles the servo kernels on first use, then caches them.
        self.status = self.console.status("starting (a first run compiles the controller: up to a minute)")
        self.started = time.perf_counter()

    def __call__(self, progress: Progress) -> None:
        """Show where the run is."""
        wall = time.perf_counter() - self.started
        factor = progress.t_s / wall if wall > 0 else 0.0
        self.status.update(
            f"line {progress.line}: {progress.statement}   t = {progress.t_s:6.2f} s   "
            f"real-time factor {factor:4.1f}"
        )


def execute_plan(session: Session, plan: Plan, progress: TerminalProgress | None) -> None:
    """Run ``plan`` on the session's arm: Ctrl-C and SIGTERM stop the arm, progress on a terminal."""
    with stop_on_signals(session.executor):
        if progress is None:
            session.executor.run(plan)
        else:
            with progress.status:
                session.executor.run(plan)


def run_program(path: Path, log_path: Path | None, rates: Rates, seed: int) -> int:
    """Run a program; print the log's path; return the exit status."""
    plan = compile_file(path)
    log_path = log_path or default_log_path(path, datetime.now(UTC))
    progress = TerminalProgress() if sys.stderr.isatty() else None
    with Session(str(path), plan.source, log_path, rates, seed, progress) as session:
        try:
            execute_plan(session, plan, progress)
        except CosmosError as error:
            session.close()
            click.echo(error.render(), err=True)
            click.echo(f"log: {session.log_path}")
            return 1
    click.echo(f"log: {session.log_path}")
    return 0
