"""The statement-boundary fsync runs beside the run, and is waited for before the file closes."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from cosmos.errors import UsageError
from cosmos.runlog.sink import LogSink


def test_close_waits_for_the_fsync_and_its_error_is_reported(tmp_path: Path) -> None:
    """Catches an fsync thread outliving the file (a closed descriptor synced, or the error lost):
    fsync on a pipe fails (EINVAL), and that failure must still be raised, naming the path."""
    read_end, write_end = os.pipe()
    stream = os.fdopen(write_end, "wb", buffering=0)
    sink = LogSink(tmp_path / "run.mcap", stream)  # type: ignore[arg-type]
    sink.write(b"x")
    sink.sync()
    sink.close()  # waits for the thread
    os.close(read_end)
    assert sink.error is not None
    with pytest.raises(UsageError, match=r"run\.mcap"):
        sink.check()


def test_syncs_share_one_thread_one_fsync_at_a_time(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches two fsyncs of one file running at once, a thread started per statement (each start
    cost the loop up to 2 ms on a loaded machine), and a sync asked for during a running fsync lost
    (its data not on disk when the file closes)."""
    running, most, calls = [0], [0], []
    real_fsync = os.fsync

    def slow_fsync(fd: int) -> None:
        running[0] += 1
        most[0] = max(most[0], running[0])
        time.sleep(0.02)
        calls.append(fd)
        real_fsync(fd)
        running[0] -= 1

    monkeypatch.setattr(os, "fsync", slow_fsync)
    before = threading.active_count()
    with (tmp_path / "f").open("wb", buffering=0) as stream:
        sink = LogSink(tmp_path / "f", stream)
        for chunk in (b"a", b"b", b"c", b"d"):
            sink.write(chunk)
            sink.sync()  # returns at once: the fsync runs beside
        assert threading.active_count() <= before + 1
        sink.wait()
        assert sink._synced == sink._asked == 4
        sink.write(b"e")
        sink.sync()
        sink.close()
    assert most[0] == 1 and 2 <= len(calls) <= 5  # asked-for syncs coalesce, the last one runs
    assert sink.error is None and (tmp_path / "f").read_bytes() == b"abcde"
    assert sink._syncer is not None and not sink._syncer.is_alive()


def test_a_run_imports_neither_the_reader_nor_the_plotting() -> None:
    """Catches `cosmos run` importing what only replay and the REPL use (start-up time, issue 20)."""
    code = (
        "import sys, cosmos.cli, cosmos.commands.run, cosmos.execution.session; "
        "print(sorted(m for m in ('cosmos.runlog.reader', 'cosmos.runlog.recover', 'mcap.reader', "
        "'matplotlib', 'prompt_toolkit', 'pandas') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def _counting_fsync(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    calls: list[int] = []
    real_fsync = os.fsync

    def fsync(fd: int) -> None:
        calls.append(fd)
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    return calls


def test_statement_syncs_within_the_interval_make_one_fsync(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches an fsync per statement again (each woke the thread, whose takes of the interpreter's
    lock cost the servo loop milliseconds a statement on a loaded machine): fifty statements' syncs
    within the interval are one fsync, done when the file closes, with all the data on disk."""
    calls = _counting_fsync(monkeypatch)
    with (tmp_path / "f").open("wb", buffering=0) as stream:
        sink = LogSink(tmp_path / "f", stream, sync_every_s=3600.0)
        for k in range(50):
            sink.write(b"%d," % k)
            sink.sync()
        assert calls == []  # asked, not done: the thread was not woken
        sink.close()
    assert len(calls) == 1 and sink.error is None
    assert (tmp_path / "f").read_bytes() == b"".join(b"%d," % k for k in range(50))


def test_an_asked_sync_is_done_within_the_interval_unasked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches syncs left to the close (a power loss during a long run would lose all of it): the
    thread wakes on its own after the interval and puts what was asked for on disk, nobody waiting."""
    calls = _counting_fsync(monkeypatch)
    with (tmp_path / "f").open("wb", buffering=0) as stream:
        sink = LogSink(tmp_path / "f", stream, sync_every_s=0.05)
        sink.write(b"a")
        sink.sync()
        deadline = time.monotonic() + 30.0
        while sink._synced < 1 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert sink._synced == 1 and len(calls) == 1
        time.sleep(0.2)  # some intervals with nothing asked: no fsync
        assert len(calls) == 1
        sink.close()
    assert len(calls) == 1  # nothing asked since: the close has nothing to sync
