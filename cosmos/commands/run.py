"""``cosmos run PROGRAM``: check, compile and run a program on the simulated arm, logged to MCAP."""

from __future__ import annotations

import sys
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING

import click

from cosmos.errors import CosmosError, UsageError
from cosmos.execution.program import StopOnSignals, TerminalProgress, execute_plan
from cosmos.execution.session import Session
from cosmos.lang import compile_program, read_program
from cosmos.plan import Plan
from cosmos.runlog.output import check_output
from cosmos.runlog.writer import unused_log_path
from cosmos.runtime.rates import Rates
from cosmos.workcell import fixture_frames

if TYPE_CHECKING:
    from cosmos.sweep.variation import WorkcellVariation


def compile_file(path: Path) -> Plan:
    """Parse, check and compile a program file; warnings go to stderr."""
    source = read_program(path)
    plan = compile_program(source, str(path), fixture_frames())
    for warning in plan.warnings:
        click.echo(warning.render(source), err=True)
    return plan


def run_program(
    path: Path,
    log_path: Path | None,
    rates: Rates,
    seed: int,
    force: bool = False,
    variation: WorkcellVariation | None = None,
    *,
    ros2: bool = False,
) -> int:
    """Run a program (in a varied workcell: ``cosmos run --vary/--sample``); print the log's path.

    The log goes to ``log_path``, or to ``logs/<stem>-<UTC time>.mcap`` (the one
    directory created if missing; ``-2``, ``-3``, ... added if that file exists).
    Ctrl-C and SIGTERM stop the arm; from before the log is opened until it is
    closed they never end the process. ``ros2``: also log the ROS 2 channels.

    Raises:
        UsageError: If the log cannot be written (it exists and not ``force``, is not
            a regular file, its directory is missing, or a write fails), naming it.
    """
    plan = compile_file(path)
    make_parents = log_path is None
    log_path = log_path or unused_log_path(path, datetime.now(UTC))
    check_output(log_path, what="the log", force=force, make_parents=make_parents)
    progress = TerminalProgress() if sys.stderr.isatty() else None
    failure: CosmosError | None = None
    with StopOnSignals() as signals:
        with Session(
            str(path), plan.source, log_path, rates, seed, progress, variation, ros2=ros2
        ) as session:
            signals.attach(session.executor)
            try:
                execute_plan(session, plan, progress)
            except UsageError:
                raise
            except CosmosError as error:
                failure = error
        # The log is closed (summary and footer written); signals still only stop the arm.
        if failure is not None:
            click.echo(failure.render(), err=True)
        click.echo(f"log: {session.log_path}")
    return 0 if failure is None else 1
