"""Compare two logged runs of one program: the state sample by sample, the events, the segments.

:func:`compare_runs` checks

- the state samples, one by one: same times (within :data:`TIME_TOLERANCE_S`),
  and every vector field (q, qd, tau, x, quat, v, wrench) within ``tolerance``
  (default one unit of the log's 1e-6 rounding), and the same segment and line;
- the events: same kind, line, statement, reason, time, and context (where the log has one:
  logs written before events carried it have none);
- the segments: same index, kind, line, statement, time, selection and setpoints.

A log cut short (killed run) or interrupted (Ctrl-C) is compared up to where it
ends. The first departure in time is reported with the statement then running.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from cosmos.runlog.reader import EventRecord, RunRecord, SegmentRecord, StateSeries
from cosmos.runlog.schemas import state_vectors

LOG_RESOLUTION = 1e-6
"""State vectors are logged rounded to 1e-6 of their unit (docs/log-format.md)."""
DEFAULT_TOLERANCE = LOG_RESOLUTION * (1 + 1e-6)
"""Two runs that round the same value on either side of a 1e-6 step still match."""
TIME_TOLERANCE_S = 1e-9
"""Times of samples, events and segments must agree this closely [s]."""

_FIRST_REPORTED = ("q", "x", "wrench", "tau")
_REPORT_ORDER = _FIRST_REPORTED + tuple(n for n, _ in state_vectors() if n not in _FIRST_REPORTED)
"""State vectors in the order their differences are reported."""
_REPORTED = 3  # differing quantities named at the first departing sample
_UNITS = {"q": "rad", "qd": "rad/s", "tau": "N m", "x": "m", "quat": "", "v": "", "wrench": ""}
_COMPONENTS = {
    "x": ["x", "y", "z"],
    "quat": ["w", "x", "y", "z"],
    "v": ["vx [m/s]", "vy [m/s]", "vz [m/s]", "wx [rad/s]", "wy [rad/s]", "wz [rad/s]"],
    "wrench": ["fx [N]", "fy [N]", "fz [N]", "mx [N m]", "my [N m]", "mz [N m]"],
}


class Found(StrEnum):
    """Which record of the runs a departure was found in."""

    STATE = "state"
    EVENTS = "events"
    SEGMENTS = "segments"


@dataclass(frozen=True)
class Departure:
    """Where a re-run first differs from the log.

    Attributes:
        t_s: Simulated time of the first difference [s].
        line: Source line of the statement the log was executing then (0: none).
        statement: Its text ("" if unknown).
        what: What differs, in words.
        found_in: Which record differs.
    """

    t_s: float
    line: int
    statement: str
    what: str
    found_in: Found = Found.STATE

    def render(self) -> str:
        """``departs at t = 1.234 s (line 5: CONTACT ...): q differs by ...``."""
        where = f"line {self.line}: {' '.join(self.statement.split())}" if self.line else "no statement"
        return f"departs at t = {self.t_s:.3f} s ({where}): {self.what}"


@dataclass(frozen=True)
class Verification:
    """The outcome of comparing a re-run with a log.

    Attributes:
        samples: State samples compared.
        events: Events compared.
        segments: Segments compared.
        until_s: End of the compared interval [s].
        departure: The earliest difference, or None if the runs match.
        also: The first difference of the other kind (state vs. events), if any.
        notes: Remarks on how the comparison was made (cut log, other version).
    """

    samples: int
    events: int
    segments: int
    until_s: float
    departure: Departure | None
    also: Departure | None
    notes: tuple[str, ...]

    @property
    def matches(self) -> bool:
        """Whether the re-run reproduces the log."""
        return self.departure is None

    def render(self) -> str:
        """The report ``cosmos replay --verify`` prints."""
        lines = [f"note: {note}" for note in self.notes]
        if self.departure is None:
            lines.append(
                f"verified: {self.samples} samples, {self.events} events match "
                f"({self.segments} segments; t = 0 .. {self.until_s:.3f} s)"
            )
        else:
            lines.append(self.departure.render())
            if self.also is not None:
                also = self.also
                verb = "differs" if also.found_in is Found.STATE else "differ"
                lines.append(f"  (the {also.found_in} first {verb} at t = {also.t_s:.3f} s: {also.what})")
        return "\n".join(lines)


def compare_runs(logged: RunRecord, again: RunRecord, tolerance: float = DEFAULT_TOLERANCE) -> Verification:
    """Compare a re-run with a logged run; see the module docstring for what is compared."""
    notes: list[str] = []
    old_version, new_version = logged.metadata.get("cosmos_version"), again.metadata.get("cosmos_version")
    if old_version != new_version:
        notes.append(f"the log was written by cosmos {old_version}; this is cosmos {new_version}")
    events, cut_s = list(logged.events), None
    if logged.truncated:
        cut_s = logged.end_time
        notes.append(f"the log is cut short at t = {cut_s:.3f} s: compared up to there")
    elif events and events[-1].kind == "interrupted":
        cut_s = events.pop().t
        notes.append(f"the run was interrupted at t = {cut_s:.3f} s: compared up to there")
    again_events = _upto(again.events, cut_s, len(events))
    again_segments = _upto(again.segments, cut_s, len(logged.segments))
    n_again = len(again.state) if cut_s is None else int(np.searchsorted(again.state.t, cut_s + 1e-9))
    if cut_s is not None:
        n_again = min(n_again, len(logged.state))

    state = _state_departure(logged, again.state, n_again, tolerance)
    event = _event_departure(events, again_events)
    if event is None:
        event = _segment_departure(logged.segments, again_segments)
    found = sorted([d for d in (event, state) if d is not None], key=lambda d: (d.t_s, d is state))
    until = cut_s if cut_s is not None else max(logged.end_time, again.end_time)
    return Verification(
        samples=min(len(logged.state), n_again),
        events=len(events),
        segments=len(logged.segments),
        until_s=until,
        departure=found[0] if found else None,
        also=found[1] if len(found) > 1 else None,
        notes=tuple(notes),
    )


def _upto(items: Sequence[EventRecord | SegmentRecord], cut_s: float | None, count: int) -> list:
    if cut_s is None:
        return list(items)
    return [item for item in items if item.t <= cut_s + TIME_TOLERANCE_S][:count]


def _statement_at(record: RunRecord, i: int) -> tuple[int, str]:
    line = int(record.state.line[i])
    index = int(record.state.segment[i])
    texts = [s.statement for s in record.segments if s.segment == index and s.line == line]
    return line, texts[0] if texts else ""


def _state_departure(
    logged: RunRecord, again: StateSeries, n_again: int, tolerance: float
) -> Departure | None:
    ours = logged.state
    n = min(len(ours), n_again)
    candidates: list[tuple[int, str]] = []
    first = _first(np.abs(ours.t[:n] - again.t[:n]) > TIME_TOLERANCE_S)
    if first is not None:
        when = f"sample {first} is at t = {ours.t[first]:.6f} s in the log, {again.t[first]:.6f} s now"
        candidates.append((first, when))
        n = first  # values are compared while the samples are at the same times
    for name in _REPORT_ORDER:
        old, new = getattr(ours, name)[:n], getattr(again, name)[:n]
        same_nan = np.isnan(old) & np.isnan(new)
        differs = (~same_nan & ~(np.abs(old - new) <= tolerance)).any(axis=1)
        index = _first(differs)
        if index is not None:
            candidates.append((index, _describe(name, old[index], new[index])))
    for name in ("segment", "line"):
        index = _first(getattr(ours, name)[:n] != getattr(again, name)[:n])
        if index is not None:
            old_value, new_value = getattr(ours, name)[index], getattr(again, name)[index]
            candidates.append((index, f"{name} is {old_value} in the log, {new_value} now"))
    if candidates:
        index = min(i for i, _ in candidates)
        what = "; ".join([text for i, text in candidates if i == index][:_REPORTED])
        t_s = min(float(ours.t[index]), float(again.t[index]))
        return Departure(t_s, *_statement_at(logged, index), what)
    if len(ours) != n_again:
        longer, shorter = ("the log", "the new run") if len(ours) > n_again else ("the new run", "the log")
        end = float(ours.t[n - 1]) if n else 0.0
        line, statement = _statement_at(logged, n - 1) if n else (0, "")
        return Departure(end, line, statement, f"{shorter} ends here; {longer} goes on")
    return None


def _first(flags: np.ndarray) -> int | None:
    hits = np.flatnonzero(flags)
    return int(hits[0]) if hits.size else None


def _describe(name: str, old: np.ndarray, new: np.ndarray) -> str:
    """``q differs by 3.1e-05 rad (joint 3: log 1.234567, now 1.234598)``."""
    delta = np.abs(old - new)
    k = int(np.nanargmax(np.where(np.isnan(delta), np.inf, delta)))
    size = "NaN" if np.isnan(delta[k]) else f"{delta[k]:.3g}"
    unit = f" {_UNITS[name]}" if _UNITS[name] else ""
    component = _COMPONENTS[name][k] if name in _COMPONENTS else f"joint {k + 1}"  # q, qd, tau
    return f"{name} differs by {size}{unit} ({component}: log {old[k]:.6f}, now {new[k]:.6f})"


def _event_text(event: EventRecord) -> str:
    reason = f" ({event.reason})" if event.reason else ""
    where = f" in {event.context}" if event.context else ""
    return f"{event.kind} of line {event.line} '{event.statement}'{where} at t = {event.t:.3f} s{reason}"


def _event_departure(ours: Sequence[EventRecord], theirs: Sequence[EventRecord]) -> Departure | None:
    for old, new in zip(ours, theirs, strict=False):
        same_time = abs(old.t - new.t) <= TIME_TOLERANCE_S
        same_context = not old.context or old.context == new.context  # "" in logs before it was kept
        if (
            (old.kind, old.line, old.reason) == (new.kind, new.line, new.reason)
            and same_time
            and same_context
        ):
            if old.statement == new.statement:
                continue
            what = (
                f"the program attached to the log reads '{new.statement}' on line {new.line}, "
                f"but the logged run executed '{old.statement}': the program was edited"
            )
        else:
            what = f"the log has the event {_event_text(old)}; the new run {_event_text(new)}"
        return Departure(min(old.t, new.t), old.line, old.statement, what, Found.EVENTS)
    if len(ours) != len(theirs):
        extra = (ours if len(ours) > len(theirs) else theirs)[min(len(ours), len(theirs))]
        which = "the log" if len(ours) > len(theirs) else "the new run"
        return Departure(
            extra.t, extra.line, extra.statement, f"only {which} has {_event_text(extra)}", Found.EVENTS
        )
    return None


def _segment_key(s: SegmentRecord) -> tuple[object, ...]:
    return (s.segment, s.line, s.statement, s.kind, s.motion_axes, len(s.goal or ()))


def _segment_numbers(s: SegmentRecord) -> np.ndarray:
    parts = [s.t, *s.frame, *s.force_setpoint, *s.stiffness, *s.damping, *(s.goal or ())]
    parts += [s.speed_limit or 0.0, s.timeout or 0.0]
    return np.array(parts)


def _segment_departure(ours: Sequence[SegmentRecord], theirs: Sequence[SegmentRecord]) -> Departure | None:
    for old, new in zip(ours, theirs, strict=False):
        if _segment_key(old) != _segment_key(new) or not np.allclose(
            _segment_numbers(old), _segment_numbers(new), rtol=1e-9, atol=TIME_TOLERANCE_S
        ):
            what = f"segment {old.segment} ({old.kind}) starts differently: its setpoint or goal differs"
            return Departure(min(old.t, new.t), old.line, old.statement, what, Found.SEGMENTS)
    if len(ours) != len(theirs):
        extra = (ours if len(ours) > len(theirs) else theirs)[min(len(ours), len(theirs))]
        which = "the log" if len(ours) > len(theirs) else "the new run"
        what = f"only {which} has segment {extra.segment}"
        return Departure(extra.t, extra.line, extra.statement, what, Found.SEGMENTS)
    return None
