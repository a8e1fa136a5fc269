"""``cosmos run PROGRAM``: check, compile and run a program on the simulated arm, logged to MCAP."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Final

import click

from cosmos.collector import collect_from_here
from cosmos.commands.plan_cache import keep_plan, load_plan, plan_file, plan_key
from cosmos.errors import CosmosError, UsageError
from cosmos.execution.program import StopOnSignals, TerminalProgress, execute_plan
from cosmos.execution.session import Session
from cosmos.hand.tool import Tool
from cosmos.lang.parse.source_file import read_program
from cosmos.plan import Plan
from cosmos.robots import robot_named
from cosmos.runlog.output import check_output, claim_log_path
from cosmos.runtime.foresight import with_foreseen_limits
from cosmos.runtime.rates import Rates
from cosmos.workcell import fixture_frames

if TYPE_CHECKING:
    from cosmos.sweep.variation import WorkcellVariation


def compile_file(path: Path, robot: str | None = None) -> Plan:
    """Parse, check and compile a program file (for the arm ``robot`` if given); warnings go to stderr.

    The plan of the last run of the same file, text, arm and cosmos is read back from the user
    cache instead (:mod:`cosmos.commands.plan_cache`): the language's modules are then not imported.
    """
    source = read_program(path)
    fixtures = fixture_frames()
    key = plan_key(source, str(path), fixtures, robot)
    kept_at = plan_file(str(path), robot)
    plan = load_plan(kept_at, key)
    if plan is None:
        from cosmos.lang import compile_program

        plan = with_foreseen_limits(compile_program(source, str(path), fixtures, robot=robot))
        keep_plan(kept_at, key, plan)
    for warning in plan.warnings:
        click.echo(warning.render(source), err=True)
    return plan


SIGNAL_STATUS_BASE: Final = 128
"""A run ended by a signal exits with 128 + its number, as shells report it: 130 for Ctrl-C."""


class _StopAndRemember(StopOnSignals):
    """:class:`StopOnSignals` that also keeps the number of the last signal received."""

    last_signal = 0

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        self.last_signal = signum
        super()._handle(signum, frame)


@dataclass(frozen=True)
class Pace:
    """Real-time pacing of a run, and its live view.

    Attributes:
        rate: Simulated seconds per wall-clock second (1: real time).
        live_port: Port of the live view's WebSocket server on 127.0.0.1 (0: any free
            port); None: no live view.
    """

    rate: float = 1.0
    live_port: int | None = None


def run_program(
    path: Path,
    log_path: Path | None,
    rates: Rates,
    seed: int,
    force: bool = False,
    variation: WorkcellVariation | None = None,
    *,
    ros2: bool = False,
    pace: Pace | None = None,
    ideal: bool = False,
    robot: str | None = None,
) -> int:
    """Run a program (in a varied workcell: ``cosmos run --vary/--sample``); print the log's path.

    The log goes to ``log_path``, or to ``logs/<stem>-<UTC time>.mcap`` (the one
    directory created if missing; ``-2``, ``-3``, ... added if that file exists).
    Ctrl-C and SIGTERM stop the arm; from before the log is opened until it is
    closed they never end the process; the status is then 128 + the signal (130:
    Ctrl-C, 143: SIGTERM). ``ros2``: also log the ROS 2 channels. ``pace``: hold
    the run to real time, and serve a live view. ``ideal``: the ideal plant (``--ideal``:
    the controller's own model, exact encoders) instead of the realistic one.

    Raises:
        UsageError: If the log cannot be written (it exists and not ``force``, is not
            a regular file, its directory is missing, or a write fails), naming it.
    """
    plan = compile_file(path, robot)
    if log_path is None:
        log_path = claim_log_path(path, datetime.now(UTC))
    else:
        check_output(log_path, what="the log", force=force, reads=(path,))
    progress = TerminalProgress() if sys.stderr.isatty() else None
    failure: CosmosError | None = None
    signals = _StopAndRemember()
    with signals:
        with Session(
            str(path),
            plan.source,
            log_path,
            rates,
            seed,
            progress,
            variation,
            ros2=ros2,
            ideal=ideal,
            robot=robot_named(plan.robot),
            tool=Tool(plan.tool),
            objects=plan.objects,
        ) as session:
            collect_from_here()
            signals.attach(session.executor)
            server = None if pace is None else session.log.pace(pace.rate, pace.live_port)
            if server is not None:
                click.echo(f"live: ws://127.0.0.1:{server.port} (Foxglove: Open connection)", err=True)
            try:
                execute_plan(session, plan, progress)
            except UsageError:
                raise
            except CosmosError as error:
                failure = error
            finally:
                if server is not None:
                    server.stop()
        # The log is closed (summary and footer written); signals still only stop the arm.
        if failure is not None:
            click.echo(failure.render(), err=True)
        click.echo(f"log: {session.log_path}")
    if signals.last_signal:
        return SIGNAL_STATUS_BASE + signals.last_signal
    return 0 if failure is None else 1
