"""A gripper run's video: its workcell rebuilt from the log, the objects and fingers where they were."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from cosmos.hand.playback_bodies import BodyTimeline, gripper_workcell
from cosmos.plant import Plant
from cosmos.robots import PUMA560
from cosmos.runlog import read_log
from tests.hand.gripper_support import hand_samples, tf_last_pose
from tests.run.run_support import PROGRAMS, run_in_process


def test_playback_puts_the_block_and_fingers_where_the_run_had_them(tmp_path: Path) -> None:
    """After pick_and_place, the video's workcell at the last /tf sample has the block where MuJoCo left it.

    Catches a video that shows the welded peg for a gripper run (the scene rebuilt without
    the gripper), objects left at their start, or fingers left open: compared with the
    block's last pose and the last opening the run logged (a body pose, not the replayed one).
    """
    log = tmp_path / "pp.mcap"
    run = run_in_process(PROGRAMS / "pick_and_place.cos", log, ideal=True)
    assert run.returncode == 0, run.describe()
    record = read_log(log)
    gripper = gripper_workcell(record)
    assert gripper is not None
    edit, objects = gripper
    assert [o.name for o in objects] == ["peg", "block_a", "block_b", "block_c", "block"]
    plant = Plant(PUMA560.scene_xml, edit_spec=edit)
    assert plant.fingers is not None
    timeline = BodyTimeline(record, objects)
    end = float(record.state.t[-1])
    timeline.apply(plant.model, plant.data, end)
    mujoco.mj_kinematics(plant.model, plant.data)
    position, _ = tf_last_pose(log, "block")
    np.testing.assert_allclose(plant.data.xpos[plant.model.body("block").id], position, atol=1e-5)
    last_opening = float(hand_samples(log)[-1]["opening"])  # type: ignore[arg-type]
    assert abs(plant.fingers.opening_m() - last_opening) < 1e-3
    assert last_opening > 0.05  # released: open
