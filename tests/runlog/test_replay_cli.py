"""``cosmos replay`` on the command line: what it prints and its exit status (called in-process:
tests/cli_in_process.py)."""

from pathlib import Path

import pytest
from mcap.reader import make_reader
from runlog_synthetic import STATEMENTS, WrittenRun, write_synthetic_run

from tests.cli_in_process import cosmos_in_process as cosmos


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> WrittenRun:
    return write_synthetic_run(tmp_path_factory.mktemp("cli") / "run.mcap")


def test_replay_prints_summary_and_timeline(written: WrittenRun) -> None:
    result = cosmos("replay", str(written.path))
    assert result.returncode == 0, result.stderr
    for statement in STATEMENTS:
        assert statement.text in result.stdout
    assert "jammed at 10 mm" in result.stdout


def test_replay_plot_writes_the_png(written: WrittenRun, tmp_path: Path) -> None:
    out = tmp_path / "run.png"
    result = cosmos("replay", str(written.path), "--plot", str(out))
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:4] == b"\x89PNG"
    assert f"plot written to {out}" in result.stdout


def test_replay_recover_completes_a_cut_log(written: WrittenRun, tmp_path: Path) -> None:
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(written.path.read_bytes()[: written.flushes[2][0] + 500])
    out = tmp_path / "fixed.mcap"
    result = cosmos("replay", str(cut), "--recover", str(out))
    assert result.returncode == 0, result.stderr
    assert "was cut short" in result.stdout and "WARNING" in result.stdout
    with open(out, "rb") as stream:
        assert make_reader(stream).get_summary() is not None


def test_missing_log_is_a_usage_error(tmp_path: Path) -> None:
    result = cosmos("replay", str(tmp_path / "none.mcap"))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr


def test_corrupt_log_fails_with_a_message_naming_it(tmp_path: Path) -> None:
    bad = tmp_path / "bad.mcap"
    bad.write_text("not a log\n")
    result = cosmos("replay", str(bad))
    assert result.returncode == 1
    assert f"{bad}: not an MCAP file" in result.stderr
    assert "Traceback" not in result.stderr


def test_a_start_past_the_logs_end_is_a_usage_error(written: WrittenRun, tmp_path: Path) -> None:
    """Catches ``--view --start 500`` on a 4 s log printing "playing from t = 500 s" and exiting 1
    (the docs give 2 for wrong usage)."""
    result = cosmos("replay", str(written.path), "--video", str(tmp_path / "v.mp4"), "--start", "500")
    assert result.returncode == 2, result.stderr
    assert "--start 500 s is past the log's end, t = 4.000 s" in result.stderr
    assert not (tmp_path / "v.mp4").exists()
