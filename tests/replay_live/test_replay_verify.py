"""``cosmos replay --verify`` on real runs: a fresh log verifies, an edited one departs where edited."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from replay_live_logs import (
    EDITED_LINE,
    EDITED_PROGRAM,
    PROGRAM,
    copy_with_source,
    cosmos,
    decoded,
    messages,
    run_to_log,
)

from cosmos.replay.compare import Found
from cosmos.replay.verify import verify_log
from cosmos.runlog import read_log
from tests.cli_in_process import cosmos_in_process

STATE = "/cosmos/state"
EVENT = "/cosmos/event"


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return run_to_log(tmp_path_factory.mktemp("verify"), PROGRAM)


def test_two_runs_in_one_process_write_identical_messages(log: Path, tmp_path: Path) -> None:
    again = run_to_log(tmp_path, PROGRAM)
    for topic in (STATE, EVENT, "/cosmos/segment", "/tf"):
        assert messages(again, topic) == messages(log, topic), topic


def test_fresh_log_verifies_in_a_new_process(log: Path) -> None:
    result = cosmos("replay", str(log), "--verify")
    assert result.returncode == 0, result.stdout + result.stderr
    samples, events = len(messages(log, STATE)), len(messages(log, EVENT))
    assert f"verified: {samples} samples, {events} events match" in result.stdout


def test_edited_program_departs_at_the_edited_statement(log: Path, tmp_path: Path) -> None:
    edited = copy_with_source(log, tmp_path / "edited.mcap", EDITED_PROGRAM)
    result = cosmos_in_process("replay", str(edited), "--verify")
    assert result.returncode == 1, result.stdout + result.stderr
    assert "Traceback" not in result.stderr
    match = re.search(r"departs at t = ([0-9.]+) s \(line (\d+): ", result.stdout)
    assert match is not None, result.stdout
    # Lines 1 and 2 are unchanged: the runs agree until line 3 starts (its start event in the log).
    edited_start = next(
        e["t"] for e in decoded(log, EVENT) if e["kind"] == "start" and e["line"] == EDITED_LINE
    )
    assert int(match.group(2)) == EDITED_LINE
    assert edited_start - 0.0005 <= float(match.group(1)) <= edited_start + 0.0105
    assert "the program was edited" in result.stdout
    # The state itself departs within a few servo ticks of the edited statement's start (with a
    # state sample at that first tick, before the events: then it is the departure named first).
    state = re.search(r"the state first differs at t = ([0-9.]+) s", result.stdout) or re.search(
        r"departs at t = ([0-9.]+) s \(line \d+: .*\): \w+ differs by", result.stdout
    )
    assert state is not None, result.stdout
    assert edited_start - 0.0005 <= float(state.group(1)) <= edited_start + 0.02  # printed to 1 ms


def test_other_settings_depart_in_the_state_of_the_first_statement(log: Path, tmp_path: Path) -> None:
    # Same program, a slower parameter evaluation: only the trajectory can tell.
    edited = copy_with_source(log, tmp_path / "slower.mcap", settings={"param_hz": "100"})
    verification = verify_log(read_log(edited))
    departure = verification.departure
    assert departure is not None
    assert departure.found_in is Found.STATE
    assert departure.line == 1
    first_done = next(e["t"] for e in decoded(log, EVENT) if e["kind"] == "done")
    assert 0.0 < departure.t_s < first_done
    assert re.match(r"\w+ differs by [0-9.e-]+", departure.what), departure.what


def test_a_failed_run_verifies_too(tmp_path: Path) -> None:
    source = "CONTACT DOWN FORCE 5 N SPEED 20 mm/s TIMEOUT 0.2 s\n"
    log = run_to_log(tmp_path, source, name="miss.cos")
    assert any(e["kind"] == "failed" for e in decoded(log, EVENT))
    verification = verify_log(read_log(log))
    assert verification.matches, verification.render()
    assert verification.samples == len(messages(log, STATE))


def test_cut_log_is_compared_up_to_the_cut(log: Path, tmp_path: Path) -> None:
    data = log.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) * 3 // 4])
    record = read_log(cut)
    assert record.truncated
    verification = verify_log(record)
    assert verification.matches, verification.render()
    assert verification.samples == len(record.state)
    assert any("cut short" in note for note in verification.notes)


def test_log_without_source_is_a_clear_error(tmp_path: Path) -> None:
    from mcap.writer import Writer

    bare = tmp_path / "bare.mcap"
    with open(bare, "wb") as stream:
        writer = Writer(stream)
        writer.start()
        writer.add_metadata("cosmos", {"program": "x.cos", "servo_hz": "1000"})
        writer.finish()
    result = cosmos_in_process("replay", str(bare), "--verify")
    assert result.returncode == 1
    assert "no program source attached" in result.stderr
    assert "Traceback" not in result.stderr


def test_interrupted_run_is_compared_up_to_the_interruption(tmp_path: Path) -> None:
    from cosmos.execution.executor import Interrupted, Progress
    from cosmos.execution.session import Session
    from cosmos.lang import compile_program
    from cosmos.runtime.rates import Rates
    from cosmos.workcell import fixture_frames

    program = str(tmp_path / "tiny.cos")
    plan = compile_program(PROGRAM, program, fixture_frames())
    log = tmp_path / "interrupted.mcap"
    with Session(program, PROGRAM, log, Rates(), 0) as session:

        def interrupt(progress: Progress) -> None:
            if progress.t_s > 0.3:  # like Ctrl-C during the first MOVE
                session.executor.stop_requested = True

        session.executor.progress = interrupt
        with pytest.raises(Interrupted):
            session.executor.run(plan)
    stopped = decoded(log, EVENT)[-1]
    assert stopped["kind"] == "interrupted"
    verification = verify_log(read_log(log))
    assert verification.matches, verification.render()
    assert any("interrupted" in note for note in verification.notes)
    assert verification.samples == len(messages(log, STATE))


def test_a_run_in_a_varied_workcell_verifies(tmp_path: Path) -> None:
    """Catches --verify re-running a varied run (cosmos run --vary, a sweep's kept log) in the
    nominal workcell: a run with a 0.5 kg payload and the hole 1 mm off "departs at t = 0.001 s"
    (its wrench differs), though nothing was edited."""
    import cosmos as api

    log = tmp_path / "varied.mcap"
    run = api.run("MOVE BY (0, 0, 20 mm)\n", log=log, vary={"payload": 0.5, "hole.x": "1 mm"}, seed=3)
    assert run.ok and "payload=0.5" in run.record.metadata["variation"]
    verification = verify_log(read_log(log))
    assert verification.departure is None, verification
