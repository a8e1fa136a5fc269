import math
from pathlib import Path

import numpy as np
import pytest
from runlog_synthetic import STATE_HZ, STATEMENTS, WrittenRun, force, write_synthetic_run

from cosmos.replay.summary import format_summary
from cosmos.replay.timeline import UNFINISHED, statement_timeline
from cosmos.runlog import read_log


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> WrittenRun:
    return write_synthetic_run(tmp_path_factory.mktemp("timeline") / "run.mcap")


def force_over(start: float, end: float) -> tuple[float, float]:
    """Peak and final |f| of the synthetic signal over the state samples in [start, end]."""
    ks = range(math.ceil(start * STATE_HZ - 1e-9), math.floor(end * STATE_HZ + 1e-9) + 1)
    magnitudes = [float(np.linalg.norm(force(k / STATE_HZ))) for k in ks]
    return max(magnitudes), magnitudes[-1]


def test_timeline_has_each_statement_with_outcome_and_forces(written: WrittenRun) -> None:
    timeline = statement_timeline(read_log(written.path))
    assert [(r.line, r.statement, r.start, r.end, r.outcome, r.reason) for r in timeline] == [
        (s.line, s.text, s.start, s.end, s.outcome, s.reason) for s in STATEMENTS
    ]
    for run, statement in zip(timeline, STATEMENTS, strict=True):
        peak, final = force_over(statement.start, statement.end)
        assert run.peak_force == pytest.approx(peak, abs=1e-5), statement.text
        assert run.final_force == pytest.approx(final, abs=1e-5), statement.text
    assert timeline[1].notes == ("contact at 1.500 s: touched",)
    assert timeline[3].peak_force == pytest.approx(25.0, abs=1e-5)  # INSERT jams at 25 N


def test_cut_log_has_an_unfinished_statement(written: WrittenRun, tmp_path: Path) -> None:
    size, _ = written.flushes[3]  # flushed just as the INSERT started (t = 3 s)
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(written.path.read_bytes()[: size + 100])
    timeline = statement_timeline(read_log(cut))
    assert [r.outcome for r in timeline] == ["done", "done", "stopped", UNFINISHED]
    assert timeline[-1].line == 5 and timeline[-1].end == pytest.approx(3.0)


def test_summary_lists_run_facts_and_statement_rows(written: WrittenRun) -> None:
    record = read_log(written.path)
    text = format_summary(record, statement_timeline(record))
    assert "programs/peg.cos" in text
    assert "servo 1000 Hz, parameters 200 Hz, state 250 Hz" in text
    assert "4.000 s of simulated time" in text
    assert "/cosmos/state" in text and f"{written.states} msgs" in text
    assert "WARNING" not in text
    rows = [line for line in text.splitlines() if line.strip()[:1].isdigit()]
    assert len(rows) == len(STATEMENTS)
    for row, statement in zip(rows, STATEMENTS, strict=True):
        fields = row.split()
        assert fields[0] == str(statement.line)
        assert statement.text in row
        assert f"{statement.start:.3f}" in fields and f"{statement.end:.3f}" in fields
        assert statement.outcome in fields
        assert row.endswith(statement.reason)
    assert "25.0 N" in rows[-1]


def test_summary_warns_about_a_cut_log(written: WrittenRun, tmp_path: Path) -> None:
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(written.path.read_bytes()[: written.flushes[2][0] + 10])
    record = read_log(cut)
    text = format_summary(record, statement_timeline(record))
    assert "WARNING: this log was cut short" in text
    assert "--recover" in text


def test_a_decision_between_statements_has_its_own_row(tmp_path: Path) -> None:
    """An IF's decision is logged between statements, where no statement is open: the summary
    dropped it, so a replay never showed which branch ran or what was read. It is a row of its
    own, at its line, with what was read, between the statements around it."""
    import cosmos

    program = "MOVE BY (0, 0, 10 mm)\nIF FORCE > 100 N\n  MOVE BY (0, 0, 10 mm)\nELSE\n"
    program += "  MOVE BY (0, 10 mm, 0)\nEND\n"
    run = cosmos.run(program, log=tmp_path / "if.mcap")
    record = read_log(tmp_path / "if.mcap")
    rows = [(r.line, r.outcome) for r in statement_timeline(record)]
    assert rows == [(1, "done"), (2, "decision"), (5, "done")], rows
    (decision,) = [e for e in run.events if e.kind == "decision"]
    text = format_summary(record, statement_timeline(record))
    assert "IF FORCE > 100 N" in text and decision.reason in text
