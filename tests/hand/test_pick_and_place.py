"""programs/pick_and_place.cos on both plants (and the Panda's with its own hand): the block ends
where the program puts it, held fast."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.hand.gripper_support import hand_samples, tf_last_pose
from tests.run.run_support import PROGRAMS, TABLE_POINT_M, run_in_process

BLOCK_HALF_HEIGHT_M = 0.025
TARGET_BASE_M = TABLE_POINT_M + np.array([0.120, 0.080, 0.0])
"""Where the program sets the block down: the table's work point + (120, 80, 0) mm (its text)."""
GRIP_N = 40.0


@pytest.mark.parametrize(
    ("program", "ideal"),
    [
        ("pick_and_place.cos", False),
        ("pick_and_place.cos", True),
        ("panda_pick_and_place.cos", True),  # the Panda's own hand; its plant is the ideal one
    ],
    ids=["realistic", "ideal", "panda"],
)
def test_pick_and_place_puts_the_block_on_its_target(tmp_path: Path, program: str, ideal: bool) -> None:
    """The 0.5 kg block ends within 2 mm and 2 deg of its target, gripped at 40 N +- 10 % while carried.

    Read from the log: the block's body pose on /tf (MuJoCo's) and the pads on /cosmos/hand.
    Catches: a held object's frame that is not the tool frame (the block lands off by the
    distance from the pads to its base), a payload that is not compensated (it sags), a grip
    that loosens or a drive that overshoots its force limit during the transfer, a RELEASE
    that knocks the block over.
    """
    log = tmp_path / "pp.mcap"
    run = run_in_process(PROGRAMS / program, log, ideal=ideal)
    assert run.returncode == 0, run.describe()
    position, quat = tf_last_pose(log, "block")
    centre_target = TARGET_BASE_M + np.array([0.0, 0.0, BLOCK_HALF_HEIGHT_M])
    assert np.linalg.norm(position - centre_target) < 0.002, position - centre_target
    # Declared AT table: the table frame's axes, RPY (180, 0, 0): quat (0, 1, 0, 0).
    tilt_deg = np.degrees(2 * np.arccos(min(1.0, abs(float(quat @ np.array([0.0, 1.0, 0.0, 0.0]))))))
    assert tilt_deg < 2.0
    grasped = run.events("done", run.line_of("GRASP block"))[0].t
    released = run.events("start", run.line_of("RELEASE", 6))[0].t
    carried = [s for s in hand_samples(log) if grasped + 0.05 < float(s["t"]) < released]  # type: ignore[arg-type]
    assert len(carried) > 100
    assert all(s["held"] == "block" for s in carried)
    forces = np.array([[s["force_left"], s["force_right"]] for s in carried], dtype=float)
    assert np.all(np.abs(forces - GRIP_N) <= 0.1 * GRIP_N), (forces.min(), forces.max())
