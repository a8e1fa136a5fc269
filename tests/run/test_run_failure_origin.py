"""A failure inside a PROC, a REPEAT pass, a WHILE pass or a TRY names where it came from (issue 14).

The compiler's errors end ``(in PROC probe called at line 7; ...)``; a statement
that fails at run time must say the same, or a user cannot tell which call or
pass failed: in ``cosmos run``'s message, in the run's outcome read back from
its log (``cosmos.run``), in the log's events, and in ``cosmos replay``'s rows.
Every failure here is a CONTACT into the air with a short TIMEOUT (the tool is
300 mm above the floor, far from the table), so each run takes a second or two;
which pass fails is decided on the measured tool height (IF/WHILE POSITION Z).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from run_support import ProgramRun, run_in_process, write_program

from cosmos.replay.summary import format_summary
from cosmos.replay.timeline import statement_timeline
from cosmos.run_result import run_from_record

AIR = "CONTACT DOWN FORCE 5 N SPEED 10 mm/s TIMEOUT 0.2 s"
NO_CONTACT = "CONTACT DOWN found no contact within 0.2 s"

CALLED_TWICE = f"""\
PROC probe(x)
  MOVE TO (x, 0.0, 0.3) SPEED 0.2 m/s
  {AIR}
  MOVE BY (0, 0, 5 mm)
END
TRY
  CALL probe(0.5)
ON FAIL
  MOVE BY (0, 0, 5 mm)
END
CALL probe(0.55)
"""
CONTACT_LINE, FIRST_CALL, TRY_LINE, SECOND_CALL = 3, 7, 6, 11

REPEATED = f"""\
PROC probe
  {AIR}
  MOVE BY (0, 0, 5 mm)
END
MOVE TO (0.5, 0.0, 0.3) SPEED 0.2 m/s
REPEAT 2
  IF POSITION Z > 0.31 m
    CALL probe
  END
  MOVE BY (0, 0, 20 mm)
END
"""
PROBE_CONTACT, REPEAT_LINE, IF_LINE, CALL_LINE, LIFT_LINE = 2, 6, 7, 8, 10

WHILE_PASSES = f"""\
MOVE TO (0.5, 0.0, 0.3) SPEED 0.2 m/s
WHILE POSITION Z < 0.33 m MAX 5
  IF POSITION Z > 0.31 m
    {AIR}
    MOVE BY (0, 0, 5 mm)
  END
  MOVE BY (0, 0, 20 mm)
END
"""
WHILE_LINE, WHILE_CONTACT = 2, 4

TOP_LEVEL = f"MOVE TO (0.5, 0.0, 0.3) SPEED 0.2 m/s\n{AIR}\n"


def _run(directory_factory: pytest.TempPathFactory, name: str, source: str) -> ProgramRun:
    directory = directory_factory.mktemp(name)
    return run_in_process(write_program(directory, name, source), directory / f"{name}.mcap", ideal=True)


@pytest.fixture(scope="module")
def called_twice(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    return _run(tmp_path_factory, "called_twice", CALLED_TWICE)


@pytest.fixture(scope="module")
def repeated(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    return _run(tmp_path_factory, "repeated", REPEATED)


def _failed(run: ProgramRun, line: int) -> list[str]:
    return [e.context for e in run.events("failed", line)]


def test_a_procedure_called_twice_names_the_call_that_failed(called_twice: ProgramRun) -> None:
    """Both calls fail; the message ``cosmos run`` prints and the run's outcome read from the log
    name the second call's line (11), the failure the TRY took over names the first (7). Catches
    a run-time failure that does not say which CALL it came from, or names the wrong one."""
    run = called_twice
    assert run.returncode == 1, run.describe()
    second = f"{NO_CONTACT} (in PROC probe called at line {SECOND_CALL})"
    name = run.program.name
    assert f"{name}:{CONTACT_LINE}:3: {second}" in run.stderr, run.stderr
    outcome = run_from_record(run.log).outcome
    assert outcome is not None and outcome.message == second
    assert f"{name}:{CONTACT_LINE}:3: {second}\n" in outcome.render()
    assert _failed(run, CONTACT_LINE) == [
        f"PROC probe called at line {FIRST_CALL}",
        f"PROC probe called at line {SECOND_CALL}",
    ]


def test_the_failure_a_try_takes_over_still_names_its_origin(called_twice: ProgramRun) -> None:
    """The TRY's ON FAIL takes over the first call's failure: the log's failure event keeps its
    context and the recovery event quotes the whole message. Catches the origin lost when a TRY
    catches the failure (only the run-ending one named)."""
    (recovery,) = called_twice.events("recovery", TRY_LINE)
    assert recovery.reason.endswith(f"{NO_CONTACT} (in PROC probe called at line {FIRST_CALL})")
    assert called_twice.events("failed", CONTACT_LINE)[0].context == f"PROC probe called at line {FIRST_CALL}"


def test_every_event_of_an_expanded_statement_carries_its_context(called_twice: ProgramRun) -> None:
    """The MOVE TO of line 2 runs once per call; its start and done events say which call.
    Catches a replay that cannot tell the calls apart (same line, same text)."""
    contexts = [(e.kind, e.context) for e in called_twice.events(line=2)]
    first, second = (f"PROC probe called at line {n}" for n in (FIRST_CALL, SECOND_CALL))
    assert contexts == [("start", first), ("done", first), ("start", second), ("done", second)]
    assert all(not e.context for e in called_twice.events(line=9))  # the ON FAIL part: top level


def test_a_failure_in_repeat_pass_two_names_the_pass_and_the_call(repeated: ProgramRun) -> None:
    """Pass 1 reads 300 mm and skips the probe; pass 2 reads 320 mm and the probe's CONTACT
    fails: the message names pass 2 of the REPEAT and the CALL inside it, outermost first, as
    the compiler words it. Catches a failure that does not say which pass, or drops a level."""
    run = repeated
    context = f"REPEAT pass 2 of 2 at line {REPEAT_LINE}; PROC probe called at line {CALL_LINE}"
    assert run.returncode == 1, run.describe()
    assert f":{PROBE_CONTACT}:3: {NO_CONTACT} (in {context})" in run.stderr, run.stderr
    assert _failed(run, PROBE_CONTACT) == [context]
    decisions = run.events("decision", IF_LINE)
    assert [d.context for d in decisions] == [f"REPEAT pass {n} of 2 at line {REPEAT_LINE}" for n in (1, 2)]


def test_the_replay_rows_tell_the_passes_apart(repeated: ProgramRun) -> None:
    """``cosmos replay``'s table leads each expanded row's reason with its short origin: the
    lift of line 10 in pass 1 and in pass 2 differ, the failed probe shows pass and call.
    Catches rows identical for every pass (the summary before this)."""
    summary = format_summary(repeated.log, statement_timeline(repeated.log))
    rows = [row for row in summary.splitlines() if re.match(rf"\s+{LIFT_LINE}\s+MOVE BY", row)]
    assert len(rows) == 1, summary  # pass 2 fails before its lift
    assert f"[pass 1/2 @{REPEAT_LINE}] arrived" in rows[0]
    (failed,) = [row for row in summary.splitlines() if re.match(rf"\s+{PROBE_CONTACT}\s+CONTACT", row)]
    assert f"[pass 2/2 @{REPEAT_LINE} > probe @{CALL_LINE}] found no contact within 0.2 s" in failed


def test_a_decision_prints_its_reading_as_the_docs_do(repeated: ProgramRun) -> None:
    """The IF's reading is the measured tool height in mm with one decimal (``read 320.0 mm``), as
    other reasons print distances, and within 0.1 mm of the logged tool point at that time.
    Catches the six significant digits it printed (``read 319.998 mm``), and a wrong scale."""
    state = repeated.log.state
    for decision in repeated.events("decision", IF_LINE):
        match = re.search(r"POSITION Z > 0\.31 m: read (-?\d+\.\d) mm;", decision.reason)
        assert match, decision.reason
        at = int((state.t <= decision.t + 1e-9).nonzero()[0][-1])
        assert float(match[1]) == pytest.approx(state.x[at, 2] * 1e3, abs=0.1)


def test_a_failure_in_a_while_pass_names_the_pass(tmp_path_factory: pytest.TempPathFactory) -> None:
    """Only the run knows a WHILE's pass: pass 1 skips the CONTACT at 300 mm, pass 2 runs it at
    320 mm and it fails: ``(in WHILE pass 2 at line 2)``. Catches a WHILE body's failure that
    does not say which pass."""
    run = _run(tmp_path_factory, "while_passes", WHILE_PASSES)
    assert run.returncode == 1, run.describe()
    context = f"WHILE pass 2 at line {WHILE_LINE}"
    assert f":{WHILE_CONTACT}:5: {NO_CONTACT} (in {context})" in run.stderr, run.stderr
    assert _failed(run, WHILE_CONTACT) == [context]
    outcome = run_from_record(run.log).outcome
    assert outcome is not None and outcome.message == f"{NO_CONTACT} (in {context})"


def test_a_top_level_failure_adds_no_origin(tmp_path_factory: pytest.TempPathFactory) -> None:
    """A statement written at top level fails with the statement and the reason only. Catches an
    empty ``(in )`` or a stray context on a statement that was not expanded."""
    run = _run(tmp_path_factory, "top_level", TOP_LEVEL)
    assert run.returncode == 1, run.describe()
    assert f"{run.program.name}:2:1: {NO_CONTACT}\n" in run.stderr, run.stderr
    assert "(in " not in run.stderr
    assert all(e.context == "" for e in run.log.events)
    outcome = run_from_record(run.log).outcome
    assert outcome is not None and outcome.message == NO_CONTACT


def test_the_repl_names_the_call_that_failed(tmp_path: Path) -> None:
    """A procedure defined in the REPL and called there fails at its CONTACT: the REPL's error
    names the call as ``cosmos run`` does. Catches the origin shown in files only."""
    from tests.repl.repl_drive import CTRL_D, ENTER, drive

    keys = ENTER.join(["PROC probe", AIR, "END", "probe", ""]) + CTRL_D
    session = drive(tmp_path, keys)
    (failed,) = [e for e in session.log.events if e.kind == "failed"]
    assert failed.context.startswith("PROC probe called at line "), failed
    assert f"{NO_CONTACT} (in {failed.context})" in session.output, session.output


def test_a_failure_in_a_retry_names_the_retry(tmp_path_factory: pytest.TempPathFactory) -> None:
    """A TRY block fails, its RETRY 1 runs it again and it fails again: the first failure has no
    origin (top level), the second names the retry, and so does the message the run ends with.
    Catches a retry's failure that reads the same as the first attempt's."""
    source = f"MOVE TO (0.5, 0.0, 0.3) SPEED 0.2 m/s\nTRY\n  {AIR}\nON FAIL\n  RETRY 1\nEND\n"
    run = _run(tmp_path_factory, "retried", source)
    assert run.returncode == 1, run.describe()
    context = "TRY retry 1 of 1 at line 2"
    assert _failed(run, 3) == ["", context]
    assert f"{NO_CONTACT} (in {context})" in run.stderr, run.stderr
