"""MOVE TO ... VIA: intermediate goals passed in order, and TIMEOUT judged on the way through them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from run_support import run_in_process, write_program

from cosmos.runlog.reader import read_log

VIAS = np.array(((0.50, 0.0, 0.40), (0.55, -0.05, 0.40)))
GOAL = np.array((0.55, -0.10, 0.35))
MOVE = "MOVE TO (0.55, -0.1, 0.35) VIA (0.5, 0.0, 0.4), (0.55, -0.05, 0.4)"


def test_the_tool_passes_each_via_point_then_reaches_the_goal(tmp_path: Path) -> None:
    run = run_in_process(write_program(tmp_path, "via", MOVE + "\n"), tmp_path / "via.mcap")
    assert run.returncode == 0, run.describe()
    x = read_log(tmp_path / "via.mcap").state.x
    # Each via point is passed within the executor's switching radius (10 mm), in order.
    first = int(np.argmin(np.linalg.norm(x - VIAS[0], axis=1)))
    second = int(np.argmin(np.linalg.norm(x - VIAS[1], axis=1)))
    assert np.linalg.norm(x[first] - VIAS[0]) < 0.012
    assert np.linalg.norm(x[second] - VIAS[1]) < 0.012
    assert first < second
    assert np.linalg.norm(x[-1] - GOAL) < 0.002


def test_a_timeout_fires_while_still_on_the_way_through_the_vias(tmp_path: Path) -> None:
    program = write_program(tmp_path, "late", MOVE + " TIMEOUT 0.5 s\n")
    run = run_in_process(program, tmp_path / "late.mcap")
    assert run.returncode == 1
    assert "timed out after 0.5 s" in run.stderr
    failed = [e for e in read_log(tmp_path / "late.mcap").events if e.kind == "failed"]
    assert failed and abs(failed[0].t - 0.5) < 0.01
