"""The field on the tool's own link moves a held tool aside, and the log says how far (issue 14).

A WAIT holds the tool; an obstacle moving through it is avoided by the field on the tool's
link (seed section 6), which acts whole and is meant to. The WAIT was "done" with nothing in
the log while the tool went 83 mm aside and back (137 mm on the Panda). Now a ``field_on_tool``
event under the WAIT names the obstacle and the largest deviation, once the field lets go of
the tool or the WAIT ends. The deviation is checked against the log's own tool points.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import cosmos

HOLD_M = np.array([0.5, 0.1, 0.4])
PROGRAM = (
    "MOVE TO (0.5, 0.1, 0.4)\n"
    "OBSTACLE ball SPHERE AT (0.5, 0.5, 0.4) RADIUS 40 mm MOVING (0, -300 mm/s, 0)\n"
    "WAIT {wait} s\n"
)


@pytest.mark.parametrize("wait_s", [2.5, 1.5], ids=["field_lets_go", "wait_ends_first"])
def test_a_tool_the_field_pushed_aside_is_told(tmp_path: Path, wait_s: float) -> None:
    """The ball passes the held tool 1.0-1.8 s into the WAIT: the event gives the largest
    distance of the tool from its hold, as the log's tool points show it (within 0.5 mm), whether
    the field let go within the WAIT (2.5 s) or the WAIT ended first (1.5 s). Catches a WAIT
    reported "done" with no word of the tool pushed tens of millimetres aside."""
    run = cosmos.run(PROGRAM.format(wait=wait_s), log=tmp_path / "aside.mcap")
    assert run.ok, run.outcome
    (moved,) = [e for e in run.events if e.kind == "field_on_tool" and e.line == 3]
    prefix = "the field of obstacle 'ball' moved the tool up to "
    assert moved.reason.startswith(prefix) and moved.reason.endswith(" mm off its path"), moved.reason
    told_mm = float(moved.reason.removeprefix(prefix).split()[0])
    state = run.record.state
    waiting = state.line == 3
    hold = state.x[waiting][0]
    measured_mm = np.linalg.norm(state.x[waiting] - hold, axis=1).max() * 1e3
    assert measured_mm > 10.0, f"the tool moved {measured_mm:.1f} mm: the ball no longer passes it"
    assert told_mm == pytest.approx(measured_mm, abs=0.5)


def test_a_links_field_reaching_the_tool_is_not_told_as_a_far_obstacles(tmp_path: Path) -> None:
    """While a post holds the Panda's link 5 back (its field reaching the tool), the tool's
    deviation is the post's. Catches it told as "the field of obstacle 'lamp' moved the tool up
    to 58.9 mm off its path": a lamp 200 mm from link 7, at the edge of its influence."""
    program = (
        "ROBOT panda\n"
        "OBSTACLE post CYLINDER AT (0.55, 0.0, 0.2) RADIUS 30 mm HEIGHT 0.35 m\n"
        "OBSTACLE lamp SPHERE AT (0.7, 0.25, 0.6) RADIUS 50 mm\n"
        "SPEED 0.2 m/s\n"
        "MOVE TO (0.55, 0.15, 0.35)\n"
        "MOVE TO (0.55, -0.15, 0.35) VIA (0.65, 0, 0.4) TIMEOUT 30 s\n"
    )
    run = cosmos.run(program, log=tmp_path / "post.mcap")
    told = [e.reason for e in run.events if e.kind == "field_on_tool"]
    assert any("link5" in reason and "post" in reason for reason in told), told
    assert not [reason for reason in told if "lamp" in reason], told
