"""A finished run as the Python API shows it: :class:`Run`, read from the run's MCAP log.

Everything in a :class:`Run` comes from the log (``cosmos.runlog.read_log``), so
a run just made and the same log loaded later are equal. Heavy modules (numpy,
pandas, matplotlib, MuJoCo) are imported inside the functions that need them:
``import cosmos`` stays cheap.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING

from cosmos.errors import CosmosError, Span, TaskFailure

if TYPE_CHECKING:
    import pandas
    from matplotlib.figure import Figure

    from cosmos.runlog.reader import EventRecord, RunRecord, SegmentRecord

PANDAS_MISSING = "Run.states needs pandas, an optional extra: pip install 'cosmos-osc[pandas]'"

_UNFINISHED_REASON = "the log ends before this statement finished"


class OutcomeKind(StrEnum):
    """How a run that did not succeed ended."""

    FAILED = "failed"
    """A statement failed on the arm (timeout, no contact, jam, ...); the arm held its pose."""
    INTERRUPTED = "interrupted"
    """The run was stopped from outside (Ctrl-C, SIGTERM); the arm held its pose."""
    UNFINISHED = "unfinished"
    """The log ends inside a statement (the process died) or is cut short."""


@dataclass(frozen=True)
class Failure:
    """Why a run did not succeed, and where in the program.

    Attributes:
        kind: Failed, interrupted or unfinished.
        t: Simulated time of the failure [s] (of the last record, if unfinished).
        span: The statement's place in the program (None: no statement, or no source).
        statement: The statement's text as logged.
        reason: The measured reason, as logged (``found no contact within 1.5 s``).
        source: The program text, to show the line.
        context: Where the statement was expanded from, as logged
            (``"PROC probe called at line 5"``; "" at top level or in an older log).
    """

    kind: OutcomeKind
    t: float
    span: Span | None
    statement: str
    reason: str
    source: str | None = field(default=None, repr=False)
    context: str = ""

    @property
    def location(self) -> str:
        """``file:line:col`` of the statement ('' if unknown)."""
        return "" if self.span is None else self.span.location

    @property
    def message(self) -> str:
        """``CONTACT UP found no contact within 1.5 s``: the statement's head, the reason, its origin.

        A statement of a PROC or a loop's pass ends with where it came from, as the
        compiler's errors do: ``... within 0.5 s (in PROC probe called at line 5)``.
        """
        from cosmos.execution.wording import (
            failure_text,
            origin,
            statement_head,
        )  # as the executor words them

        if self.kind is OutcomeKind.INTERRUPTED:  # as the executor's Interrupted says it
            return f"{statement_head(self.statement)} interrupted{origin(self.context)}"
        return failure_text(self.statement, self.reason, self.context)

    def error(self) -> TaskFailure:
        """The failure as the exception ``cosmos run`` reports (``raise run.outcome.error()``)."""
        return TaskFailure(self.message, self.span, self.source)

    def render(self) -> str:
        """``file:line:col: message``, the source line and a caret, as ``cosmos run`` prints it."""
        return self.error().render()

    def __str__(self) -> str:
        return self.render()


@dataclass(frozen=True, eq=False, repr=False)
class Run:
    """A run of a program on the simulated arm, as its log records it.

    Two Runs are equal when they hold the same data (a run and ``cosmos.load`` of its log).

    Attributes:
        log_path: The MCAP log, an absolute path.
        program: The program's name as given (a path, or ``<program>`` for text).
        source: The program text attached to the log.
        seed: Seed of the wrist sensor's noise (None: not recorded).
        ok: True if every statement finished: no failure, no interruption, log complete.
        outcome: Why the run did not succeed, with the statement's location; None if ``ok``.
        events: Statement starts and ends, contacts, collisions, warnings, in time order.
        segments: The plan's segments as they started (task frame, axes, setpoints).
        duration_s: Simulated time of the run's last record [s].
        record: Everything read from the log (numpy arrays in ``record.state``).
    """

    log_path: Path
    program: str
    source: str | None
    seed: int | None
    ok: bool
    outcome: Failure | None
    events: tuple[EventRecord, ...]
    segments: tuple[SegmentRecord, ...]
    duration_s: float
    record: RunRecord = field(repr=False)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Run):
            return NotImplemented
        names = [f.name for f in fields(self) if f.name != "record"]
        if any(getattr(self, name) != getattr(other, name) for name in names):
            return False
        return _same_state(self.record, other.record)

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        outcome = "ok" if self.outcome is None else f"{self.outcome.kind.value} at {self.outcome.location}"
        return (
            f"Run({self.program!r}, {outcome}, {self.duration_s:.3f} s, {len(self.events)} events, "
            f"{len(self.record.state)} states, log_path={str(self.log_path)!r})"
        )

    @property
    def states(self) -> pandas.DataFrame:
        """The ``/cosmos/state`` samples, one row each, a new DataFrame on each access.

        Columns: ``t`` [s], ``segment``, ``line`` (0: no statement), the joint angles
        named after the arm's joints (``joint1`` .. ``joint<n>``) [rad], the tool point
        ``x y z`` [m] and orientation ``qw qx qy qz`` in the world frame, and the wrench
        the tool applies to the environment ``fx fy fz`` [N] ``mx my mz`` [N m]
        (world axes, moment about the tool point). Values not finite in the log are NaN.

        Raises:
            CosmosError: pandas is not installed.
        """
        try:
            import pandas
        except ImportError:
            raise CosmosError(PANDAS_MISSING) from None
        state = self.record.state
        columns = {"t": state.t, "segment": state.segment, "line": state.line}
        columns |= {f"joint{i + 1}": state.q[:, i] for i in range(state.q.shape[1])}
        columns |= {name: state.x[:, i] for i, name in enumerate(("x", "y", "z"))}
        columns |= {name: state.quat[:, i] for i, name in enumerate(("qw", "qx", "qy", "qz"))}
        columns |= {name: state.wrench[:, i] for i, name in enumerate(("fx", "fy", "fz", "mx", "my", "mz"))}
        return pandas.DataFrame({name: values.copy() for name, values in columns.items()})

    def plot(self, path: str | Path | None = None) -> Figure:
        """The run's figure (as ``cosmos replay LOG --plot``): tool position and force against time.

        Args:
            path: Also write it there as a PNG.

        Raises:
            CosmosError: The log has no state samples, or the file cannot be written.
        """
        from cosmos.replay.plot import figure_for_run
        from cosmos.replay.timeline import statement_timeline

        figure = figure_for_run(self.record, statement_timeline(self.record))
        if path is not None:
            out = Path(path)
            try:
                out.parent.mkdir(parents=True, exist_ok=True)
                figure.savefig(out, dpi=100)
            except OSError as error:
                raise CosmosError(f"{out}: cannot write the plot: {error.strerror or error}") from None
        return figure


def run_from_record(record: RunRecord) -> Run:
    """The :class:`Run` a log holds."""
    outcome = _outcome(record)
    seed = record.metadata.get("seed")
    return Run(
        log_path=record.path.absolute(),
        program=record.metadata.get("program", record.path.name),
        source=record.source,
        seed=int(seed) if seed is not None and seed.lstrip("-").isdigit() else None,
        ok=outcome is None,
        outcome=outcome,
        events=record.events,
        segments=record.segments,
        duration_s=record.end_time,
        record=record,
    )


def _same_state(a: RunRecord, b: RunRecord) -> bool:
    import numpy as np

    def same(x: np.ndarray | None, y: np.ndarray | None) -> bool:
        if x is None or y is None:  # the fingers' fields: None without the gripper
            return x is y
        return bool(np.array_equal(x, y, equal_nan=True))

    return all(same(getattr(a.state, f.name), getattr(b.state, f.name)) for f in fields(a.state))


def _outcome(record: RunRecord) -> Failure | None:
    """The first failure (not one a TRY took over) or interruption; else the statement left open."""
    program = record.metadata.get("program", record.path.name)
    open_starts: list[EventRecord] = []
    events = record.events
    for index, event in enumerate(events):
        kind = None
        if event.kind == "failed" and index + 1 < len(events) and events[index + 1].kind == "recovery":
            # a TRY's ON FAIL part took this failure over: the statement ended, the run goes on
            match = [i for i, start in enumerate(open_starts) if start.line == event.line]
            del open_starts[match[-1] if match else len(open_starts) :]
            continue
        if event.kind == "failed":
            kind = OutcomeKind.FAILED
        elif event.kind == "interrupted" or (event.kind == "stopped" and event.reason == "interrupted"):
            # (logs written before "interrupted" was an outcome of its own said it this way)
            kind = OutcomeKind.INTERRUPTED
        if kind is not None:
            return _failure(kind, event, event.reason, program, record.source)
        if event.kind == "start":
            open_starts.append(event)
        elif event.kind in ("done", "stopped"):
            match = [i for i, start in enumerate(open_starts) if start.line == event.line]
            del open_starts[match[-1] if match else len(open_starts) :]
    if open_starts or record.truncated:
        last = open_starts[-1] if open_starts else None
        t = record.end_time
        if last is None:
            return Failure(OutcomeKind.UNFINISHED, t, None, "", "the log is cut short", record.source)
        return _failure(OutcomeKind.UNFINISHED, last, _UNFINISHED_REASON, program, record.source, t)
    return None


def _failure(
    kind: OutcomeKind,
    event: EventRecord,
    reason: str,
    program: str,
    source: str | None,
    t: float | None = None,
) -> Failure:
    span = statement_span(program, event.line, event.statement, source)
    return Failure(kind, event.t if t is None else t, span, event.statement, reason, source, event.context)


def statement_span(program: str, line: int, statement: str, source: str | None) -> Span | None:
    r"""Where a logged statement is in the program: its line, and its column found in that line.

    A statement continued on the next line (``\``) is logged with its lines joined;
    its span then runs from its start to the end of its first line.
    """
    if source is None:
        return None
    lines = source.splitlines()
    if not 1 <= line <= len(lines):
        return None
    text = lines[line - 1]
    start = text.find(statement) if statement else -1
    if start >= 0:
        return Span(program, line, start + 1, line, start + 1 + len(statement))
    prefix = next((statement[:k] for k in range(len(statement), 0, -1) if statement[:k] in text), "")
    column = text.find(prefix) + 1 if prefix else len(text) - len(text.lstrip()) + 1
    return Span(program, line, column, line + 1, 1)
