"""``cosmos repl`` from the shell: lines piped to stdin, the log path printed, exit status."""

from __future__ import annotations

import io
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from cosmos.errors import UsageError
from cosmos.repl.app import ReplApp
from cosmos.runlog.reader import read_log


def test_piped_session_runs_and_logs_under_logs(tmp_path: Path) -> None:
    typed = "FRAME a = table + (0, 0, 200 mm)\nWAIT 0.1 s\nPROC w\n  WAIT 0.05 s\nEND\nw\nWAIT 1 mx\n:log\n"
    done = subprocess.run(
        [sys.executable, "-m", "cosmos", "repl"],
        input=typed,
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    out = done.stdout
    assert "Traceback" not in out + done.stderr
    (log,) = (tmp_path / "logs").glob("repl-*.mcap")  # the default path
    assert out.count(f"log: logs/{log.name}") == 3  # at the start, for :log, at the end
    assert "cosmos> WAIT 0.1 s\nok  WAIT 0.1 s" in out
    assert "cosmos> PROC w\n.......   WAIT 0.05 s\n....... END\nPROC w defined" in out
    assert "<repl>:7:8: 'mx' is not a unit" in out
    record = read_log(log)
    assert record.source is not None and record.source.splitlines()[6] == "# ! WAIT 1 mx"
    assert [e.statement for e in record.events if e.kind == "done"] == ["WAIT 0.1 s", "WAIT 0.05 s"]


def test_bytes_that_are_not_utf8_are_refused_at_their_line_and_the_log_keeps_the_session(
    tmp_path: Path,
) -> None:
    """Catches a byte that is not UTF-8 in a piped line (a comment ``# caf\\xe9``): the session
    ran, then ended in a traceback (``UnicodeEncodeError`` attaching the transcript), exit 1,
    and the log had no program source for ``cosmos replay --verify``."""
    log = tmp_path / "bytes.mcap"
    done = subprocess.run(
        [sys.executable, "-m", "cosmos", "repl", "--log", str(log)],
        input=b"WAIT 0.1 s\n# caf\xe9\nWAIT 0.05 s\n",
        capture_output=True,
        timeout=120,
        cwd=tmp_path,
    )
    out = done.stdout.decode("utf-8", "replace")
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in out + done.stderr.decode("utf-8", "replace")
    assert "<repl>:2:6: the input is not UTF-8 text (byte 0xe9 cannot be read)" in out
    record = read_log(log)
    assert record.source == "WAIT 0.1 s\n# ! # caf\ufffd\nWAIT 0.05 s\n"
    assert [e.statement for e in record.events if e.kind == "done"] == ["WAIT 0.1 s", "WAIT 0.05 s"]


def test_sigterm_at_the_prompt_ends_the_session_with_a_complete_log(tmp_path: Path) -> None:
    log = tmp_path / "term.mcap"
    child = subprocess.Popen(
        [sys.executable, "-m", "cosmos", "repl", "--log", str(log)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert child.stdin is not None and child.stdout is not None
    child.stdin.write("WAIT 0.1 s\n")
    child.stdin.flush()
    seen = ""
    while "ok  WAIT 0.1 s" not in seen:  # the statement ran; the REPL now waits for a line
        line = child.stdout.readline()
        assert line, "the REPL ended early"
        seen += line
    child.send_signal(signal.SIGTERM)
    out, err = child.communicate(timeout=60)
    assert child.returncode == 1, err
    assert "session ended by SIGTERM" in out and "Traceback" not in out + err
    record = read_log(log)
    assert not record.truncated
    assert record.source == "WAIT 0.1 s\n"


def test_unwritable_log_is_a_usage_error(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(UsageError, match="cannot write the log"):
        ReplApp(blocker / "x.mcap", io.StringIO(), stdin=io.StringIO())


def test_repl_log_follows_the_run_rules(tmp_path: Path) -> None:
    """Catches ``cosmos repl --log`` overwriting an existing file or creating a typed directory.

    ``cosmos run`` refuses both in one line (``--force`` overwrites); the REPL used to
    truncate the file and make the directory silently.
    """
    from cosmos.commands.repl import run_repl

    kept = tmp_path / "kept.mcap"
    kept.write_bytes(b"earlier session")
    with pytest.raises(UsageError, match="kept.mcap: already exists; pass --force"):
        run_repl(kept)
    assert kept.read_bytes() == b"earlier session"
    with pytest.raises(UsageError, match="no such directory"):
        run_repl(tmp_path / "missing" / "x.mcap")
    assert not (tmp_path / "missing").exists()
