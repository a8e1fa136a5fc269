"""The Python API: :func:`run`, :func:`load` and :func:`check`, as ``cosmos.run`` etc.

They drive the same layers as the command line: ``cosmos run`` (compile, a
:class:`~cosmos.execution.session.Session`, its executor), ``cosmos replay``
(``read_log``) and ``cosmos check`` (``compile_program``). A run's result is
read back from the log the run wrote, so ``run(...) == load(run(...).log_path)``.

Mistakes raise :class:`~cosmos.errors.CosmosError` (a path that cannot be read,
a program that does not compile, a bad rate) with the file and place; a
statement that fails on the arm does not raise: ``Run.ok`` is False and
``Run.outcome`` says where and why.
"""

from __future__ import annotations

import os
import threading
import warnings
from collections.abc import Callable, Mapping
from contextlib import nullcontext
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING

from cosmos.errors import CosmosError, TaskFailure, UsageError
from cosmos.run_result import Run, run_from_record

if TYPE_CHECKING:
    from cosmos.execution.executor import Progress
    from cosmos.plan import Plan

TEXT_NAME = "<program>"
"""The file name that errors and the log give a program passed as text."""

ProgramArg = str | os.PathLike[str]


class CosmosWarning(UserWarning):
    """A program compiles but likely does not do what was meant (``cosmos check``'s warnings)."""


def _is_path(program: str) -> bool:
    """Whether a string names a program file rather than holding program text."""
    if "\n" in program or ";" in program:
        return False
    if program.strip().endswith(".cos"):
        return True
    try:
        return Path(program).is_file()
    except (OSError, ValueError):
        return False


def read_program(program: ProgramArg, name: str | None = None) -> tuple[str, str]:
    """A program's text and the name its errors carry (its path, or ``<program>`` for text).

    A string is a path if it is one line that ends in ``.cos`` or names an existing
    file; otherwise it is the program's text.

    Raises:
        UsageError: The file cannot be read, or ``program`` is neither text nor a path.
        ProgramError: The file is not UTF-8.
    """
    from cosmos.lang import read_source

    if isinstance(program, os.PathLike) or (isinstance(program, str) and _is_path(program)):
        path = Path(program)
        if path.is_dir():
            raise UsageError(f"{path}: is a directory, not a program file")
        return read_source(path), name or str(program)
    if not isinstance(program, str):
        raise UsageError(f"a program is a path or its text, not {type(program).__name__}")
    return program, name or TEXT_NAME


def _rate(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise UsageError(f"{name} must be a number [Hz]; got {value!r}")
    return float(value)


def check(program: ProgramArg, *, name: str | None = None, robot: str | None = None) -> Plan:
    """Parse, check and compile a program (a path or its text) as ``cosmos check`` does.

    Args:
        program: A ``.cos`` file, or the program's text.
        name: The file name that errors carry (default: the path, or ``<program>``).
        robot: The arm to check for (``--robot``); a program's ROBOT must agree.

    Returns:
        The plan: its ``steps`` (segments and scene changes) and ``warnings``.

    Raises:
        ProgramError: A syntax or check error: ``str(error)`` is ``file:line:col: message``,
            the line and a caret; ``error.span`` has the place.
        UsageError: The file cannot be read.
    """
    from cosmos.lang import compile_program
    from cosmos.runtime.foresight import with_foreseen_limits
    from cosmos.workcell import fixture_frames

    source, file = read_program(program, name)
    try:
        return with_foreseen_limits(compile_program(source, file, fixture_frames(), robot=robot))
    except CosmosError as error:
        raise error.with_source(source) from None


def load(log: str | os.PathLike[str]) -> Run:
    """The :class:`Run` a log records (a log of ``cosmos run``, ``cosmos.run`` or the REPL).

    Raises:
        CosmosError: The file does not exist, is not MCAP or is not a cosmos log
            (one line naming the path and the reason).
    """
    from cosmos.runlog.reader import read_log

    return run_from_record(read_log(Path(log)))


def run(
    program: ProgramArg,
    *,
    log: str | os.PathLike[str] | None = None,
    seed: int = 0,
    servo_hz: float | None = None,
    param_hz: float | None = None,
    name: str | None = None,
    progress: Callable[[Progress], None] | None = None,
    ideal: bool = False,
    robot: str | None = None,
    vary: Mapping[str, float | str] | None = None,
) -> Run:
    """Run a program on the simulated arm, as ``cosmos run`` does, and return what the log records.

    Args:
        program: A ``.cos`` file, or the program's text.
        log: The MCAP log to write (``--log``); default ``logs/<program>-<UTC time>.mcap``.
        seed: Seed of the wrist sensor's noise and of the realistic plant's drawn model
            error and sensor bias (``--seed``).
        servo_hz: Servo rate [Hz] (``--servo-hz``; default 1000).
        param_hz: Parameter-evaluation rate [Hz] (``--param-hz``; default 125, at most
            the servo rate).
        name: The file name that errors and the log carry (default: the path, or ``<program>``).
        progress: Called every 200 servo ticks with the statement running and the time.
        ideal: Run the ideal plant (``--ideal``: the controller's own model, exact encoders
            and velocities) instead of the realistic one (``cosmos.realism``).
        robot: The arm (``--robot``: ``puma560`` or ``panda``); a program's ROBOT must agree.
            Default: the program's ROBOT, else the PUMA 560.
        vary: The real workcell varied (``--vary``, docs/sweep.md): a value per parameter, a
            number in its SI unit or a string with units (``{"hole.x": "1 mm", "payload": 0.3}``).

    Returns:
        The run, read from its log. A statement that failed on the arm does not raise:
        ``ok`` is False and ``outcome`` names the statement, its place and the reason.
        Ctrl-C (in the main thread) stops the arm, which holds, and ends the run the same way.

    Raises:
        ProgramError: The program does not compile (with file, line and column).
        UsageError: The file cannot be read, a rate is out of range, or a ``vary`` is not known.
    """
    from cosmos.execution.program import stop_on_signals
    from cosmos.execution.session import Session
    from cosmos.hand.tool import Tool
    from cosmos.robots import robot_named
    from cosmos.runlog.output import check_output, claim_log_path
    from cosmos.runtime.rates import Rates

    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise UsageError(f"seed must be a whole number from 0 up; got {seed!r}")
    if not isinstance(ideal, bool):
        raise UsageError(f"ideal must be True or False; got {ideal!r}")
    rates = Rates.chosen(
        None if servo_hz is None else _rate(servo_hz, "servo_hz"),
        None if param_hz is None else _rate(param_hz, "param_hz"),
    )
    variation = None
    if vary:
        from cosmos.sweep.variation import constant_variation

        texts = [
            f"{key}={value!r}" if isinstance(value, float | int) else f"{key}={value}"
            for key, value in vary.items()
        ]
        variation = constant_variation(texts, seed, ideal)
    plan = check(program, name=name, robot=robot)
    for warning in plan.warnings:
        warnings.warn(warning.render(plan.source), CosmosWarning, stacklevel=2)
    stem = Path("program" if plan.file == TEXT_NAME else plan.file)
    log_path = Path(log) if log is not None else claim_log_path(stem, datetime.now(UTC))
    if log is not None:  # overwritten if it exists, as open() would; never the program itself
        reads = () if plan.file == TEXT_NAME else (Path(plan.file),)
        check_output(log_path, what="the log", force=True, make_parents=True, reads=reads)
    failure: TaskFailure | None = None
    try:
        session = Session(
            plan.file,
            plan.source,
            log_path,
            rates,
            seed,
            progress,
            variation,
            ideal=ideal,
            robot=robot_named(plan.robot),
            tool=Tool(plan.tool),
            objects=plan.objects,
        )
    except OSError as error:  # the log cannot be created there
        raise UsageError(f"{log_path}: cannot write the log: {error.strerror or error}") from None
    with session:
        in_main = threading.current_thread() is threading.main_thread()
        with stop_on_signals(session.executor) if in_main else nullcontext():
            try:
                session.executor.run(plan)
            except TaskFailure as error:  # the log has it; the Run reports it
                failure = error
    result = load(session.log_path)
    if failure is not None and result.ok:
        raise CosmosError(
            f"{session.log_path}: the run failed ({failure.message}) but its log says it succeeded"
        )
    return result
