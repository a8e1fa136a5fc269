"""A goal motion that something blocks fails after a stall instead of pushing for ever."""

from __future__ import annotations

import re
from pathlib import Path

from run_support import run_in_process, write_program

from cosmos.runlog.reader import read_log

# From home (tool 257 mm above the table top) straight down 300 mm: 43 mm into the table.
INTO_THE_TABLE = "MOVE BY (0, 0, -300 mm) SPEED 0.1 m/s\n"


def test_a_move_into_the_table_fails_once_it_stops_getting_closer(tmp_path: Path) -> None:
    run = run_in_process(write_program(tmp_path, "blocked", INTO_THE_TABLE), tmp_path / "blocked.mcap")
    assert run.returncode == 1
    assert re.search(r"blocked\.cos:1:1: MOVE BY is blocked: stopped \d+ mm short .* pushing", run.stderr)
    record = read_log(tmp_path / "blocked.mcap")
    failed = [e for e in record.events if e.kind == "failed"]
    # 2.6 s to reach the table at 0.1 m/s, then the 2 s stall window.
    assert failed and 4.0 < failed[0].t < 6.0


def test_a_pose_out_of_reach_fails_saying_so(tmp_path: Path) -> None:
    run = run_in_process(write_program(tmp_path, "far", "MOVE TO (2, 0, 0.5)\n"), tmp_path / "far.mcap")
    assert run.returncode == 1
    assert "far.cos:1:1: MOVE TO cannot reach its goal" in run.stderr
    assert "out of the arm's reach" in run.stderr
