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


def test_a_move_on_a_compliant_spring_settles_short_of_a_blocked_goal(tmp_path: Path) -> None:
    # Z is a 100 N/m spring: pressed on the table it rests where the spring balances.
    program = "MOVE TO table + (0, 0, 20 mm)\nCOMPLY Z STIFFNESS 100 N/m\nMOVE BY (0, 0, -40 mm)\n"
    run = run_in_process(write_program(tmp_path, "spring", program), tmp_path / "spring.mcap")
    assert run.returncode == 0, run.describe()
    done = [e for e in read_log(tmp_path / "spring.mcap").events if e.kind == "done" and e.line == 3]
    assert done and done[0].reason.startswith("settled on its COMPLY spring")
