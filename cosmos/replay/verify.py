"""``cosmos replay --verify``: re-run the program stored in a log and compare, sample by sample.

The simulation is deterministic: the same program with the same servo,
parameter and state rates and the same seed gives the same trajectory, bit for
bit. :func:`verify_log` re-runs the log's source attachment (compiled under the
program path recorded in the metadata) into a temporary log and compares the
two with :func:`cosmos.replay.compare.compare_runs`.
"""

from __future__ import annotations

import sys
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

from cosmos.errors import CosmosError, ProgramError, TaskFailure
from cosmos.replay.compare import DEFAULT_TOLERANCE, Verification, compare_runs
from cosmos.runlog.reader import RunRecord, read_log
from cosmos.runtime.rates import Rates

REPL_PROGRAM = "<repl>"
"""The ``program`` of a REPL session's log; its source is the session's transcript."""


@dataclass(frozen=True)
class RunSettings:
    """What a run was started with, read back from its log's metadata and attachment."""

    program: str
    source: str
    rates: Rates
    seed: int


def settings_from_log(record: RunRecord) -> RunSettings:
    """The program, source, rates and seed a logged run was started with.

    Raises:
        CosmosError: If the log has no program source or lacks a setting.
    """
    meta = record.metadata
    if record.source is None:
        raise CosmosError(f"{record.path}: no program source attached: nothing to re-run")
    try:
        rates = Rates(float(meta["servo_hz"]), float(meta["param_hz"]), float(meta["state_hz"]))
        seed = int(meta.get("seed", "0"))
    except KeyError as missing:
        raise CosmosError(f"{record.path}: the metadata has no {missing}: cannot re-run alike") from None
    except ValueError as error:
        raise CosmosError(f"{record.path}: a setting in the metadata is malformed: {error}") from None
    program = meta.get("program") or record.source_name or "<log>"
    return RunSettings(program=program, source=record.source, rates=rates, seed=seed)


def rerun(settings: RunSettings, log_path: Path) -> str | None:
    """Run ``settings.source`` on a fresh arm, logged to ``log_path``.

    Returns:
        The failure message if a statement failed (the log is complete either way), else None.

    Raises:
        CosmosError: If the program does not compile (any more), or the run is interrupted.
    """
    from cosmos.commands.run import TerminalProgress, execute_plan
    from cosmos.execution.executor import Interrupted
    from cosmos.execution.session import Session
    from cosmos.lang import compile_program
    from cosmos.workcell import fixture_frames

    try:
        plan = compile_program(settings.source, settings.program, fixture_frames())
    except ProgramError as error:
        raise CosmosError(f"the program stored in the log does not compile:\n{error.render()}") from None
    progress = TerminalProgress() if sys.stderr.isatty() else None
    with Session(settings.program, plan.source, log_path, settings.rates, settings.seed, progress) as session:
        try:
            execute_plan(session, plan, progress)
        except Interrupted:
            raise CosmosError("--verify: the re-run was interrupted") from None
        except TaskFailure as failure:
            return failure.message
    return None


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
    with tempfile.TemporaryDirectory(prefix="cosmos-verify-") as directory:
        rerun(settings, Path(directory) / "rerun.mcap")
        again = read_log(Path(directory) / "rerun.mcap")
    verification = compare_runs(record, again, tolerance)
    if settings.program == REPL_PROGRAM and not verification.matches:
        note = (
            "a REPL session re-runs as one program of its transcript: it departs after a "
            "failed statement or a :reset, which a program does not go past"
        )
        return replace(verification, notes=(*verification.notes, note))
    return verification
