"""A reorienting MOVE arrives at its goal orientation and the WAIT after it holds it there.

Arrival is "within tolerance (1 mm, 1 deg) and at rest", but rest was judged on the tool
point's speed alone: a MOVE that turned the tool 66 deg ended as soon as the turn was within
1 deg, the tool still turning at 11 deg/s, and the WAIT after it held the measured pose of that
instant, 0.75 deg (ideal plant) to 0.80 deg (realistic) off the goal, on every RPY chain. Arrival
now also asks the tool's controlled rotations to be at rest
(:data:`cosmos.execution.arrival.REST_ANGULAR_SPEED_RAD_S`, 2.9 deg/s), so the MOVE ends and the
WAIT holds within 0.35 deg. (The last tenths of a degree creep in at 3.5-4.6 /s on both plants, slower
than eq. 20-21's double root at -20 /s: not traced.)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from run_support import BOTH_PLANTS, run_in_process, write_program

SETTLED_DEG = 0.4
"""The orientation error a settled MOVE and its WAIT may keep [deg] (the tester saw 0.75-0.84)."""
POSITION_M = 0.5e-3
"""Its tool point's error [m] (0.06-0.42 mm before the change)."""

ROLL, PITCH, YAW = 150.0, 30.0, 45.0
PROGRAMS = {
    "puma560": f"MOVE TO (0.55, -0.1, 0.45) RPY ({ROLL:g} deg, {PITCH:g} deg, {YAW:g} deg)\nWAIT 3 s\n",
    "panda": (
        "ROBOT panda\nMOVE TO (0.55, -0.15, 0.4) RPY (180 deg, 0, 0)\n"
        f"MOVE TO (0.55, -0.15, 0.4) RPY ({ROLL:g} deg, {PITCH:g} deg, {YAW:g} deg)\nWAIT 3 s\n"
    ),
}
GOAL_M = {"puma560": np.array((0.55, -0.1, 0.45)), "panda": np.array((0.55, -0.15, 0.4))}


def goal_rotation() -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)`` built here from elementary rotations (docs/language.md's RPY)."""
    r, p, y = np.radians((ROLL, PITCH, YAW))
    rx = np.array(((1, 0, 0), (0, math.cos(r), -math.sin(r)), (0, math.sin(r), math.cos(r))))
    ry = np.array(((math.cos(p), 0, math.sin(p)), (0, 1, 0), (-math.sin(p), 0, math.cos(p))))
    rz = np.array(((math.cos(y), -math.sin(y), 0), (math.sin(y), math.cos(y), 0), (0, 0, 1)))
    return rz @ ry @ rx


def angle_from_deg(quat_wxyz: np.ndarray, rotation: np.ndarray) -> float:
    """The angle of ``R(q) rotation^T`` [deg], from the trace (independent of the controller's log)."""
    w, x, y, z = quat_wxyz / np.linalg.norm(quat_wxyz)
    measured = np.array(
        (
            (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
            (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
            (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
        )
    )
    cosine = (np.trace(measured @ rotation.T) - 1.0) / 2.0
    return math.degrees(math.acos(min(1.0, max(-1.0, cosine))))


@pytest.mark.parametrize("arm", sorted(PROGRAMS))
@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_reorienting_move_arrives_and_its_wait_holds_the_goal_orientation(
    tmp_path: Path, arm: str, ideal: bool
) -> None:
    """The run's log: the measured tool orientation at the MOVE's end and at the WAIT's end is
    within 0.4 deg of the goal's RPY (computed here), its tool point within 0.5 mm. Catches the
    arrival that ended the MOVE 0.8 deg short while still turning (the WAIT kept 0.75-0.80 deg)."""
    program = write_program(tmp_path, f"settle_{arm}", PROGRAMS[arm])
    run = run_in_process(program, tmp_path / "settle.mcap", ideal=ideal)
    assert run.returncode == 0, run.describe()
    move_line, wait_line = run.line_of("RPY (150"), run.line_of("WAIT")
    state = run.log.state
    for line in (move_line, wait_line):
        last = np.flatnonzero(state.line == line)[-1]
        off_deg = angle_from_deg(state.quat[last], goal_rotation())
        off_m = float(np.linalg.norm(state.x[last] - GOAL_M[arm]))
        assert off_deg <= SETTLED_DEG, f"line {line}: {off_deg:.3f} deg off\n{run.describe()}"
        assert off_m <= POSITION_M, f"line {line}: {off_m * 1e3:.2f} mm off\n{run.describe()}"
