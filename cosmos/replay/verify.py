"""``cosmos replay --verify``: re-run the program stored in a log and compare, sample by sample.

The simulation is deterministic: the same program with the same servo,
parameter and state rates and the same seed gives the same trajectory, bit for
bit. :func:`verify_log` re-runs the log's source attachment (compiled under the
program path recorded in the metadata) into a temporary log and compares the
two with :func:`cosmos.replay.compare.compare_runs`.

The log is untrusted: its settings are checked against the ranges ``cosmos
run`` accepts, its program is compiled (and checked) like any program, and the
re-run is stopped once it passes :func:`time_bound` of simulated time, twice
the logged run's duration plus 10 s: a run that reproduces the log ends well
before, and a program that would run without end (``WAIT`` for ever) does not.
"""

from __future__ import annotations

import math
import sys
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from cosmos.errors import CosmosError, ProgramError, TaskFailure, UsageError
from cosmos.lang.parse.source_file import MAX_PROGRAM_BYTES
from cosmos.replay.compare import DEFAULT_TOLERANCE, Verification, compare_runs
from cosmos.robots import ROBOTS
from cosmos.runlog.printable import printable
from cosmos.runlog.reader import RunRecord, read_log
from cosmos.runtime.rates import PHYSICS_HZ, Rates

if TYPE_CHECKING:
    import numpy as np

    from cosmos.execution.executor import Executor
    from cosmos.runtime.loop import Recorder
    from cosmos.sweep.variation import WorkcellVariation

REPL_PROGRAM = "<repl>"
"""The ``program`` of a REPL session's log; its source is the session's transcript."""


BOUND_FACTOR = 2.0
BOUND_MARGIN_S = 10.0


def time_bound(logged_s: float) -> float:
    """Simulated time after which a re-run is stopped [s]: ``2 * logged_s + 10``."""
    return BOUND_FACTOR * logged_s + BOUND_MARGIN_S


class TimeBound:
    """Stops the run once simulated time passes ``limit_s``: it sees every state sample recorded.

    Installed as the runtime's recorder in front of the real one, so it is
    consulted at the state rate whatever the program does (many short
    statements, one long ``WAIT``); the executor stops at its next tick.

    Args:
        limit_s: The bound [s].
        executor: The executor to stop.
        recorder: The recorder it stands in front of.
    """

    def __init__(self, limit_s: float, executor: Executor, recorder: Recorder):
        self.limit_s = limit_s
        self.executor = executor
        self.recorder = recorder
        self.stopped_at_s: float | None = None

    def record(self, t_s: float, *sample: np.ndarray) -> None:
        """Pass the sample on; ask the executor to stop if it is past the bound."""
        if t_s > self.limit_s and self.stopped_at_s is None:
            self.stopped_at_s = t_s
            self.executor.stop_requested = True
        self.recorder.record(t_s, *sample)


@dataclass(frozen=True)
class RunSettings:
    """What a run was started with, read back from its log's metadata and attachment."""

    program: str
    source: str
    rates: Rates
    seed: int
    ideal: bool = True
    model_error: float | None = None
    robot: str = "puma560"
    variation: WorkcellVariation | None = None


def settings_from_log(record: RunRecord) -> RunSettings:
    """The program, source, rates, seed and plant a logged run was started with.

    The plant is the metadata's ``plant`` (``realistic`` with its ``model_error``, drawn
    again from the seed; ``ideal``); a log from before the realistic plant has none and
    was made on the ideal one. A run in a varied workcell (``cosmos run --vary``, a sweep's
    run) has the variation as ``cosmos run`` arguments (``variation``): it is made again.

    Raises:
        CosmosError: If the log has no program source or lacks a setting.
    """
    meta = record.metadata
    if record.source is None:
        raise CosmosError(f"{record.path}: no program source attached: nothing to re-run")
    if len(record.source.encode(errors="replace")) > MAX_PROGRAM_BYTES:  # as a program file
        raise CosmosError(
            f"{record.path}: the program attached is larger than {MAX_PROGRAM_BYTES:,} bytes: not re-run"
        )
    try:
        servo_hz = _setting(meta, "servo_hz", 1.0, PHYSICS_HZ)
        param_hz = _setting(meta, "param_hz", 1.0, servo_hz)
        state_hz = _setting(meta, "state_hz", 100.0, PHYSICS_HZ)
        seed = int(meta.get("seed", "0"))
        if not 0 <= seed < 2**63:
            raise ValueError("seed is outside 0 .. 2**63 - 1")
        rates = Rates(servo_hz, param_hz, state_hz)
        ideal, model_error = _plant_settings(meta)
        variation = _variation(meta.get("variation", ""), seed)
    except KeyError as missing:
        raise CosmosError(f"{record.path}: the metadata has no {missing}: cannot re-run alike") from None
    except (ValueError, UsageError) as error:
        message = error.message if isinstance(error, UsageError) else str(error)
        raise CosmosError(f"{record.path}: a setting in the metadata is malformed: {message}") from None
    program = meta.get("program") or record.source_name or "<log>"
    robot = meta.get("robot", "puma560")  # logs before the Panda ran the PUMA
    if robot not in ROBOTS:
        raise CosmosError(
            f"{record.path}: the metadata names the robot {robot[:40]!r}, which this cosmos has not"
        )
    return RunSettings(
        program=program,
        source=record.source,
        rates=rates,
        seed=seed,
        ideal=ideal,
        model_error=model_error,
        robot=robot,
        variation=variation,
    )


def _variation(arguments: str, seed: int) -> WorkcellVariation | None:
    """The workcell of the metadata's ``variation`` (``--ideal --vary 'NAME=VALUE' ...``), if any."""
    import shlex

    from cosmos.sweep.variation import constant_variation

    if not arguments:
        return None
    words = shlex.split(arguments)
    ideal = words[:1] == ["--ideal"]
    pairs = words[1:] if ideal else words
    if len(pairs) % 2 or any(option != "--vary" for option in pairs[::2]):
        raise ValueError(f"variation = {arguments[:80]!r} is not cosmos run's --vary arguments")
    return constant_variation(pairs[1::2], seed, ideal)


def _plant_settings(meta: Mapping[str, str]) -> tuple[bool, float | None]:
    """``(ideal, model_error)`` from the metadata (module docstring of :mod:`cosmos.realism`)."""
    from cosmos.realism.plant_realism import IDEAL, REALISTIC

    plant = meta.get("plant", IDEAL)
    if plant not in (IDEAL, REALISTIC):
        raise ValueError(f"plant = {plant!r} is neither {IDEAL!r} nor {REALISTIC!r}")
    if plant == IDEAL:
        return True, None
    model_error = float(meta["model_error"])
    if not (math.isfinite(model_error) and model_error >= 0.0):
        raise ValueError(f"model_error = {model_error!r} is not a finite number >= 0")
    return False, model_error


def _setting(meta: Mapping[str, str], name: str, low: float, high: float) -> float:
    value = float(meta[name])
    if not (math.isfinite(value) and low <= value <= high):
        raise ValueError(f"{name} = {value:g} is outside {low:g} .. {high:g} Hz")
    return value


def rerun(settings: RunSettings, log_path: Path, limit_s: float = math.inf) -> float | None:
    """Run ``settings.source`` on a fresh arm, logged to ``log_path``, for at most ``limit_s``.

    A failed statement ends the re-run as it ended the run; the log is complete either way.

    Returns:
        The simulated time at which the re-run was stopped for passing ``limit_s``, else None.

    Raises:
        CosmosError: If the program does not compile (any more), or the run is interrupted.
    """
    from cosmos.execution.executor import Interrupted
    from cosmos.execution.program import StopOnSignals, TerminalProgress, execute_plan
    from cosmos.execution.session import Session
    from cosmos.hand.tool import Tool
    from cosmos.lang import compile_program
    from cosmos.robots import robot_named
    from cosmos.workcell import fixture_frames

    try:
        plan = compile_program(settings.source, settings.program, fixture_frames(), robot=settings.robot)
    except ProgramError as error:
        rendered = printable(error.render(), keep_newlines=True)
        raise CosmosError(f"the program stored in the log does not compile:\n{rendered}") from None
    progress = TerminalProgress() if sys.stderr.isatty() else None
    rates, seed = settings.rates, settings.seed
    with StopOnSignals() as signals:
        with Session(
            settings.program,
            plan.source,
            log_path,
            rates,
            seed,
            progress,
            settings.variation,
            ideal=settings.ideal,
            model_error=settings.model_error,
            robot=robot_named(plan.robot),
            tool=Tool(plan.tool),
            objects=plan.objects,
        ) as session:
            signals.attach(session.executor)
            recorder = session.runtime.recorder
            assert recorder is not None  # the session logs
            bound = TimeBound(limit_s, session.executor, recorder)
            session.runtime.recorder = bound
            try:
                execute_plan(session, plan, progress)
            except Interrupted:
                if bound.stopped_at_s is None:
                    raise CosmosError("--verify: the re-run was interrupted") from None
            except TaskFailure:
                pass
    return bound.stopped_at_s


def verify_log(record: RunRecord, tolerance: float = DEFAULT_TOLERANCE) -> Verification:
    """Re-run the program of ``record`` with its settings and compare the new run with it.

    Args:
        record: The log, as read by :func:`cosmos.runlog.read_log`.
        tolerance: Largest difference of a state vector component still taken
            as equal, in the component's SI unit.

    Raises:
        CosmosError: If the log cannot be re-run (no source, missing settings,
            the program does not compile).
    """
    settings = settings_from_log(record)
    limit_s = time_bound(record.end_time)
    with tempfile.TemporaryDirectory(prefix="cosmos-verify-") as directory:
        stopped_at_s = rerun(settings, Path(directory) / "rerun.mcap", limit_s)
        again = read_log(Path(directory) / "rerun.mcap")
    verification = compare_runs(record, again, tolerance)
    if stopped_at_s is not None:
        note = (
            f"the re-run was stopped at t = {stopped_at_s:.3f} s, past its bound of {limit_s:g} s "
            f"(twice the logged {record.end_time:.3f} s, plus {BOUND_MARGIN_S:g} s)"
        )
        verification = replace(verification, notes=(*verification.notes, note))
    if settings.program == REPL_PROGRAM and not verification.matches:
        note = (
            "a REPL session re-runs as one program of its transcript: it departs after a "
            "failed statement or a :reset, which a program does not go past"
        )
        return replace(verification, notes=(*verification.notes, note))
    return verification
