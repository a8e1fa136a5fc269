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


def test_a_via_leg_that_stops_getting_closer_fails_with_its_cause(tmp_path: Path) -> None:
    """A VIA leg held back fails as a last leg does (2 s without progress), naming the point and the cause.

    Bug: the stall judge ran only on the last leg, so a leg that a post's field held 31 mm from its
    VIA point pushed for ever (4265 s of simulated time until interrupted); with this TIMEOUT the
    MOVE failed at 30 s, "timed out", with no cause.
    """
    program = write_program(
        tmp_path,
        "held",
        "ROBOT panda\n"
        "OBSTACLE post CYLINDER AT (0.55, 0.0, 0.2) RADIUS 30 mm HEIGHT 0.35 m\n"
        "SPEED 0.2 m/s\n"
        "MOVE TO (0.55, 0.15, 0.35)\n"
        "MOVE TO (0.55, -0.15, 0.35) VIA (0.65, 0, 0.4) TIMEOUT 30 s\n",
    )
    run = run_in_process(program, tmp_path / "held.mcap")
    assert run.returncode == 1, run.describe()
    log = read_log(tmp_path / "held.mcap")
    failed = [e for e in log.events if e.kind == "failed"]
    start = next(e.t for e in log.events if e.kind == "start" and e.line == 5)
    assert failed and failed[0].line == 5
    assert failed[0].reason.startswith("cannot reach its VIA point 1 at (650, 0, 400) mm: stopped ")
    assert "the field of obstacle 'post' holds it back" in failed[0].reason
    # The tool measured when it failed is as far from the VIA point as the reason says.
    said_mm = float(failed[0].reason.split("stopped ")[1].split(" mm")[0])
    at_failure = int(np.searchsorted(log.state.t, failed[0].t)) - 1
    measured_mm = 1e3 * float(np.linalg.norm(log.state.x[at_failure] - np.array((0.65, 0.0, 0.4))))
    assert abs(said_mm - measured_mm) < 1.0
    assert failed[0].t - start < 15.0  # its 2 s without progress, not the TIMEOUT's 30 s
