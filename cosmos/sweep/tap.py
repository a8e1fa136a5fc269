"""What a sweep keeps of a run, taken from the values the run log is given as they are written.

Reading a run's log back (``cosmos.load``) costs 10-20 % of a short run's own simulation, most
of it decoding the state samples; a sweep needs only the events and the wrench. A
:class:`LogTap` wraps the session's :class:`~cosmos.runlog.writer.RunLog` so that each event
and each state sample goes to the log as before and its few needed values are kept in memory.
``tests/sweep/test_worker.py`` checks that the summary from a tap equals the one read from the
run's log.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from cosmos.runlog.reader import EventRecord
from cosmos.runlog.writer import RunLog


class LogTap:
    """Keeps the events and, per state sample, its time, line and force magnitude."""

    def __init__(self, log: RunLog) -> None:
        self.events: list[EventRecord] = []
        self.samples: list[tuple[float, int, float]] = []  # (t [s], line, |f| [N])
        write_event, write_state = log.event, log.state

        def event(
            t: float, kind: str, *, line: int, statement: str, reason: str = "", context: str = ""
        ) -> None:
            write_event(t, kind, line=line, statement=statement, reason=reason, context=context)
            self.events.append(EventRecord(t, kind, line, statement, reason, context))

        def state(t: float, *vectors: Any) -> None:
            write_state(t, *vectors)
            wrench, line = vectors[6], vectors[8]
            self.samples.append((t, int(line), math.hypot(wrench[0], wrench[1], wrench[2])))

        log.event = event  # type: ignore[method-assign]
        log.state = state  # type: ignore[method-assign,assignment]

    def summary(self) -> dict[str, Any]:
        """:func:`summarize` of what was tapped."""
        if not self.samples:
            return summarize(self.events, np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0))
        t, line, force = (np.array(column) for column in zip(*self.samples, strict=True))
        return summarize(self.events, t, line, force)


def summarize(
    events: Sequence[EventRecord], t: ArrayLike, line: ArrayLike, force: ArrayLike
) -> dict[str, Any]:
    """A run's outcome, duration and, per statement, its duration and peak force.

    Args:
        events: The run's events in time order.
        t: State sample times [s]. # (n,)
        line: Each sample's statement line. # (n,)
        force: Each sample's force magnitude the tool applies [N]. # (n,)

    Returns:
        ``ok``, ``outcome`` (``ok``, ``failed``, ``interrupted``), ``line``, ``statement`` and
        ``reason`` of the first failure that no TRY took over (as ``cosmos.run_result`` reads
        them from a log),
        ``duration_s``, ``peak_force_n`` and ``statements`` (``line``, ``statement``,
        ``duration_s``, ``peak_force_n`` each).
    """
    from cosmos.execution.wording import statement_head

    times, lines, forces = np.asarray(t, dtype=float), np.asarray(line), np.asarray(force, dtype=float)
    statements = []
    starts: dict[int, tuple[float, str]] = {}
    failure: EventRecord | None = None
    for index, event in enumerate(events):
        recovered = index + 1 < len(events) and events[index + 1].kind == "recovery"  # a TRY took it over
        if (
            failure is None
            and not recovered
            and (event.kind in ("failed", "interrupted") or _old_interrupted(event))
        ):
            failure = event
        if event.kind == "start":
            starts[event.line] = (event.t, event.statement)
        elif event.kind in ("done", "failed", "stopped", "interrupted") and event.line in starts:
            t0, statement = starts.pop(event.line)
            during = (lines == event.line) & (times >= t0) & (times <= event.t)
            peak = float(np.nanmax(forces[during])) if during.any() else 0.0
            statements.append(
                {
                    "line": event.line,
                    "statement": statement_head(statement),
                    "duration_s": event.t - t0,
                    "peak_force_n": peak,
                }
            )
    end = max([0.0] + [float(times[-1])] * bool(len(times)) + [e.t for e in events[-1:]])
    return {
        "ok": failure is None,
        "outcome": "ok" if failure is None else ("failed" if failure.kind == "failed" else "interrupted"),
        "line": None if failure is None else failure.line,
        "statement": None if failure is None else statement_head(failure.statement),
        "reason": None if failure is None else failure.reason,
        "duration_s": end,
        "peak_force_n": float(np.nanmax(forces)) if len(forces) else 0.0,
        "statements": statements,
    }


def _old_interrupted(event: EventRecord) -> bool:
    """An interruption as logs said it before it was an event of its own (``cosmos.run_result``)."""
    return event.kind == "stopped" and event.reason == "interrupted"
