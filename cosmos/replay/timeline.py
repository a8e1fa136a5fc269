"""What each statement of a run did, from the log's events and state samples."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from cosmos.runlog.reader import RunRecord
from cosmos.runlog.schemas import OUTCOME_KINDS, EventKind

UNFINISHED = "unfinished"
"""Outcome of a statement whose end is not in the log (the run was cut short)."""


@dataclass(frozen=True)
class StatementRun:
    """One execution of a statement.

    Attributes:
        line: Source line.
        statement: Source text.
        start: Simulated time of its start event [s].
        end: Time of its outcome event [s]; the end of the log if it has none.
        outcome: done, stopped, failed, or ``unfinished``; for an event between statements
            (``decision``, ``recovery``, ``retry``), its kind.
        reason: The outcome event's reason.
        peak_force: Largest |f| the tool applied during the statement [N] (NaN: no sample).
        final_force: |f| at the last sample of the statement [N] (NaN: no sample).
        notes: Contacts, collisions and warnings during it, as ``kind: reason``.
        depth: Nesting depth (a statement started while another was running).
        context: Where an expanded statement came from, as its start event logs it
            (``"PROC probe called at line 5"``); "" at top level or in an older log.
    """

    line: int
    statement: str
    start: float
    end: float
    outcome: str
    reason: str
    peak_force: float
    final_force: float
    notes: tuple[str, ...]
    depth: int
    context: str = ""

    @property
    def between(self) -> bool:
        """An event between statements (a decision, a recovery, a retry), not a statement's run."""
        return self.outcome != UNFINISHED and self.outcome not in OUTCOME_KINDS


@dataclass
class _Open:
    line: int
    statement: str
    start: float
    depth: int
    context: str = ""
    notes: list[str] = field(default_factory=list)


def _innermost(stack: list[_Open], line: int) -> int | None:
    """Index of the innermost open statement of ``line`` in ``stack``."""
    return next((i for i in reversed(range(len(stack))) if stack[i].line == line), None)


def statement_timeline(record: RunRecord) -> list[StatementRun]:
    """The statements of a run in order of start, with outcome and forces.

    A ``start`` event opens a statement; the next ``done``, ``stopped`` or
    ``failed`` event of the same line closes it (and any statement started
    inside it that is still open). Other events become notes of the innermost
    open statement; between statements (a decision, a recovery, a retry) a row of
    their own, its outcome the event's kind.
    """
    runs: list[StatementRun] = []
    stack: list[_Open] = []
    t = record.state.t
    force = record.state.force_magnitude

    def close(item: _Open, end: float, outcome: str, reason: str) -> None:
        inside = (t >= item.start) & (t <= end)
        if outcome == EventKind.STOPPED:
            # The first sample at or after an UNTIL fired belongs to the statement it stopped.
            fired = int(np.searchsorted(t, end - 1e-9))
            if fired < len(t):
                inside[fired] = True
        peak = float(force[inside].max()) if inside.any() else float("nan")
        final = float(force[inside][-1]) if inside.any() else float("nan")
        runs.append(
            StatementRun(
                line=item.line,
                statement=item.statement,
                start=item.start,
                end=end,
                outcome=outcome,
                reason=reason,
                peak_force=peak,
                final_force=final,
                notes=tuple(item.notes),
                depth=item.depth,
                context=item.context,
            )
        )

    for event in record.events:
        if event.kind == EventKind.START:
            stack.append(_Open(event.line, event.statement, event.t, len(stack), event.context))
        elif event.kind in OUTCOME_KINDS:
            match = _innermost(stack, event.line)
            if match is None:  # an end without a start: show it as an instant
                item = _Open(event.line, event.statement, event.t, len(stack), event.context)
                close(item, event.t, event.kind, event.reason)
                continue
            while len(stack) > match + 1:
                close(stack.pop(), event.t, UNFINISHED, "its enclosing statement ended")
            close(stack.pop(), event.t, event.kind, event.reason)
        elif stack:
            note = f"{event.kind} at {event.t:.3f} s"
            stack[-1].notes.append(f"{note}: {event.reason}" if event.reason else note)
        else:  # between statements: an IF's or WHILE's decision, a TRY's recovery, a RETRY
            nan = float("nan")
            runs.append(
                StatementRun(
                    event.line,
                    event.statement,
                    event.t,
                    event.t,
                    event.kind,
                    event.reason,
                    nan,
                    nan,
                    (),
                    0,
                    event.context,
                )
            )
    end = record.end_time
    while stack:
        close(stack.pop(), end, UNFINISHED, "no outcome in the log")
    runs.sort(key=lambda run: (run.start, run.depth))
    return runs
