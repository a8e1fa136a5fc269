"""The statement-boundary fsync runs beside the run, and is waited for before the file closes."""

from __future__ import annotations

import os
import subprocess
import sys
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


def test_a_sync_after_a_sync_waits_for_the_first(tmp_path: Path) -> None:
    """Catches two fsyncs of one file running at once (a thread per statement piling up)."""
    with (tmp_path / "f").open("wb", buffering=0) as stream:
        sink = LogSink(tmp_path / "f", stream)
        sink.write(b"abc")
        sink.sync()
        first = sink._syncing
        sink.sync()
        assert first is not None and not first.is_alive()
        sink.close()
    assert sink.error is None and (tmp_path / "f").read_bytes() == b"abc"


def test_a_run_imports_neither_the_reader_nor_the_plotting() -> None:
    """Catches `cosmos run` importing what only replay and the REPL use (start-up time, issue 20)."""
    code = (
        "import sys, cosmos.cli, cosmos.commands.run, cosmos.execution.session; "
        "print(sorted(m for m in ('cosmos.runlog.reader', 'cosmos.runlog.recover', 'mcap.reader', "
        "'matplotlib', 'prompt_toolkit', 'pandas') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
