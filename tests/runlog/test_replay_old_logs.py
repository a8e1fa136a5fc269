"""A log written before events carried their context still replays (issue 14).

Events gained a ``context`` field (where a statement expanded from a PROC, REPEAT,
WHILE or TRY came from); the logs written before have none and must read, sum up
and verify as they did.
"""

from __future__ import annotations

from pathlib import Path

from crafted_logs import event, write_log

from cosmos.replay.compare import compare_runs
from cosmos.replay.summary import format_summary
from cosmos.replay.timeline import statement_timeline
from cosmos.run_result import run_from_record
from cosmos.runlog import read_log

EVENTS = [
    event(t=0.0, kind="start", line=1),
    event(t=0.076, kind="failed", line=1, reason="timed out after 0.1 s"),
]


def test_a_log_written_before_contexts_replays(tmp_path: Path) -> None:
    """Events without ``context`` read as top level: the timeline, the summary row and the
    outcome are as before. Catches a reader that requires the new field, or a summary that
    shows an empty origin."""
    assert all("context" not in e for e in EVENTS)
    record = read_log(write_log(tmp_path / "old.mcap", events=EVENTS))
    assert [e.context for e in record.events] == ["", ""]
    summary = format_summary(record, statement_timeline(record))
    (row,) = [r for r in summary.splitlines() if r.strip().startswith("1  MOVE BY")]
    assert row.rstrip().endswith("  timed out after 0.1 s")
    assert "[" not in row
    outcome = run_from_record(record).outcome
    assert outcome is not None and outcome.message == "MOVE BY timed out after 0.1 s"


def test_an_old_log_verifies_against_a_run_that_logs_contexts(tmp_path: Path) -> None:
    """Comparing an old log (no contexts) with a new run of the same program (contexts) finds no
    departure in the events; a context that differs is one. Catches ``replay --verify`` failing
    every old log of a program with a PROC, or ignoring a run that took another pass."""
    old = read_log(write_log(tmp_path / "old.mcap", events=EVENTS))
    with_context = [dict(e, context="PROC p called at line 4") for e in EVENTS]
    new = read_log(write_log(tmp_path / "new.mcap", events=with_context))
    assert compare_runs(old, new).departure is None
    other = [dict(e, context="PROC p called at line 5") for e in EVENTS]
    departure = compare_runs(new, read_log(write_log(tmp_path / "other.mcap", events=other))).departure
    assert departure is not None and "in PROC p called at line 4" in departure.what
