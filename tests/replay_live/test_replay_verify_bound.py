"""``cosmos replay --verify`` re-runs an untrusted program only for twice the logged time plus 10 s."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from replay_live_logs import copy_with_source, run_to_log

from cosmos.cli import main
from cosmos.replay.verify import time_bound, verify_log
from cosmos.runlog import read_log


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return run_to_log(tmp_path_factory.mktemp("bound"), "WAIT 0.1 s\n")


@pytest.mark.parametrize("program", ["WAIT 100 s\n", "WAIT 0.1 s\n" * 200], ids=["one-long", "many-short"])
def test_a_program_that_waits_for_ever_is_stopped_at_the_bound(
    log: Path, tmp_path: Path, program: str
) -> None:
    """Catches --verify running whatever the attached program says for as long as it says (the
    issue's WAIT 1e308 s ran until killed): a log of a 0.1 s run carrying a 100 s WAIT, or 200
    statements too short for the progress display to see, is re-run for 2 * 0.1 + 10 s of
    simulated time, then reported as departing, with the bound named."""
    logged = read_log(log)
    hostile = copy_with_source(log, tmp_path / "hostile.mcap", source=program)
    limit = time_bound(logged.end_time)
    assert limit == 2 * logged.end_time + 10
    verification = verify_log(read_log(hostile))
    assert not verification.matches
    (note,) = [n for n in verification.notes if "bound" in n]
    stopped_at = float(note.split("stopped at t = ")[1].split(" s")[0])
    assert limit < stopped_at < limit + 0.5  # stopped at the bound, not at the WAIT's end
    assert f"bound of {limit:g} s" in note


def test_the_command_says_what_the_bound_is(
    log: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches a bound that is applied without the user being told."""
    monkeypatch.setattr(sys, "argv", ["cosmos", "replay", str(log), "--verify"])
    with pytest.raises(SystemExit) as exit_status:
        main()
    out, err = capsys.readouterr()
    assert exit_status.value.code == 0, err
    bound = time_bound(read_log(log).end_time)
    assert f"stopped if it passes t = {bound:g} s: twice the logged" in out
    assert "verified:" in out
