"""Ctrl-C or SIGTERM during ``cosmos run``: the arm stops and holds, the log is complete."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from mcap.reader import make_reader
from run_support import REPO, write_program

from cosmos.runlog.reader import read_log

LONG = "MOVE BY (0, 0, 50 mm)\nWAIT 600 s\n"


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_stops_the_run_and_closes_a_valid_log(tmp_path: Path, signum: int) -> None:
    program, log = write_program(tmp_path, "long", LONG), tmp_path / "long.mcap"
    process = subprocess.Popen(
        [sys.executable, "-m", "cosmos", "run", str(program), "--log", str(log)],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60.0
    while not (log.exists() and log.stat().st_size > 20_000) and time.monotonic() < deadline:
        time.sleep(0.2)  # until the run is well under way
    process.send_signal(signum)
    stdout, stderr = process.communicate(timeout=60)
    assert process.returncode == 128 + signum  # 130 for Ctrl-C, 143 for SIGTERM, as shells report
    assert "interrupted" in stderr and "Traceback" not in stderr
    assert f"log: {log}" in stdout
    with log.open("rb") as f:
        assert make_reader(f).get_summary() is not None  # complete: summary and footer
    record = read_log(log)
    assert not record.truncated
    assert [e.kind for e in record.events][-1] == "interrupted"  # not "stopped": that is an UNTIL
