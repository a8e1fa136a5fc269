"""The blocks of TOOL GRIPPER's workcell: where the docs put them, at rest, and graspable."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cosmos.errors import ProgramError
from cosmos.lang import compile_program
from cosmos.workcell import fixture_frames
from tests.hand.gripper_support import tf_last_pose
from tests.run.run_support import run_in_process, write_program

TABLE_TOP_Z_M = 0.20
BLOCKS = {  # docs/language.md, "The gripper's workcell": base centre x, y [m], height [m]
    "block_a": (0.44, 0.02, 0.050),
    "block_b": (0.44, 0.10, 0.030),
    "block_c": (0.44, 0.18, 0.040),
}
PICK_B = """TOOL GRIPPER
SPEED 0.2 m/s
MOVE TO table + (-160 mm, 250 mm, 100 mm)
MOVE TO table + (-160 mm, 250 mm, 12.5 mm) SPEED 50 mm/s
GRASP block_b FORCE 30 N WIDTH 30 mm
MOVE BY (0, 0, 50 mm) SPEED 0.1 m/s
"""


def test_the_gripper_workcell_has_the_blocks() -> None:
    """Catches: blocks missing from TOOL GRIPPER's workcell, or left in a TOOL PEG one."""
    names = [o.name for o in compile_program("TOOL GRIPPER\n", "t.cos", fixture_frames()).objects]
    assert names == ["peg", *BLOCKS]
    assert compile_program("MOVE BY (0, 0, 10 mm)\n", "t.cos", fixture_frames()).objects == ()
    with pytest.raises(ProgramError, match="one of its blocks"):
        compile_program(
            "TOOL GRIPPER\nOBJECT block_a BOX SIZE (40 mm, 30 mm, 50 mm) MASS 0.5 kg AT table\n",
            "t.cos",
            fixture_frames(),
        )


@pytest.mark.parametrize("ideal", [False, True], ids=["realistic", "ideal"])
def test_block_b_is_picked_and_the_others_stay(tmp_path: Path, ideal: bool) -> None:
    """GRASP block_b where the docs put it lifts it 50 mm; block_a and block_c stay where the docs
    say, upright on the table (MuJoCo's body poses on /tf).

    Catches: a block placed elsewhere than documented (the GRASP closes on nothing), a block
    that starts in the table or above it (it sinks or falls and moves), blocks on the arm's way.
    """
    log = tmp_path / "b.mcap"
    run = run_in_process(write_program(tmp_path, "b", PICK_B), log, ideal=ideal)
    assert run.returncode == 0, run.describe()
    for name, (x, y, height) in BLOCKS.items():
        position, quat = tf_last_pose(log, name)
        lift = 0.050 if name == "block_b" else 0.0
        expected = np.array([x, y, TABLE_TOP_Z_M + height / 2 + lift])
        tolerance = 0.003 if name == "block_b" else 0.001
        assert np.linalg.norm(position - expected) < tolerance, (name, position - expected)
        if name != "block_b":
            assert abs(abs(float(quat[1])) - 1.0) < 1e-3, (name, quat)  # z down, as placed: upright


def test_blocks_at_rest_sleep(tmp_path: Path) -> None:
    """After the arm has held 0.5 s, MuJoCo has put every resting block to sleep: its tree
    asleep and none of its contacts in the step (MuJoCo's own data).

    Catches: islands or sleep off in a workcell with objects (the blocks' twelve contacts with
    the table then cost every tick about as much as the rest of the physics step).
    """
    import mujoco

    from cosmos.hand.work_object import SHIPPED_OBJECTS
    from tests.hand.gripper_support import gripper_session

    with gripper_session(tmp_path, ideal=False, objects=SHIPPED_OBJECTS) as session:
        session.executor.hold(0.5)
        model, data = session.plant.model, session.plant.data
        for name in BLOCKS:
            body = model.body(name).id
            assert data.tree_asleep[model.body_treeid[body]] >= 0, name
            geoms = {model.geom(f"{name}_geom").id, model.geom(f"{name}_seat").id}  # grip and seat
            touching = [c for c in data.contact[: data.ncon] if geoms & {c.geom1, c.geom2}]
            assert touching == [], name
        assert model.opt.enableflags & int(mujoco.mjtEnableBit.mjENBL_SLEEP)


@pytest.mark.parametrize("height_mm", [12.5, 15.0, 20.0])
def test_a_block_lifted_off_the_table_is_no_collision(tmp_path: Path, height_mm: float) -> None:
    """A block grasped where it stands lifts off the table without a protective stop.

    Catches the lift's start judged by MuJoCo's contacts alone: block_b grasped 15 mm up
    (ideal plant) rested a fraction of a millimetre above the table when the lift began, no
    contact in MuJoCo's list, so the table it touched again 4 ms later was a new contact:
    "protective stop: block_b hit fixture 'table' at 5.20 s, 0.4 N". A tool *at* a fixture
    (within 0.5 mm, MuJoCo's distances) starts in contact with it, as a touching one does.
    """
    program = PICK_B.replace("100 mm)", "80 mm)").replace("12.5 mm) SPEED 50", f"{height_mm} mm) SPEED 40")
    program = program.replace("FORCE 30 N WIDTH 30 mm", "FORCE 35 N").replace(
        "(0, 0, 50 mm) SPEED 0.1 m/s", "(0, 0, 80 mm)"
    )
    log = tmp_path / "lift.mcap"
    run = run_in_process(write_program(tmp_path, "lift", program), log, ideal=True)
    assert run.returncode == 0, run.describe()
    position, _ = tf_last_pose(log, "block_b")
    assert position[2] > TABLE_TOP_Z_M + 0.015 + 0.075, position  # lifted 80 mm (the grip may slip 5 mm)


STACK_B_ON_C = """TOOL GRIPPER
SPEED 0.2 m/s
MOVE TO table + (-160 mm, 250 mm, 80 mm)
MOVE TO table + (-160 mm, 250 mm, 15 mm) SPEED 40 mm/s
GRASP block_b FORCE 35 N
MOVE BY (0, 0, 60 mm)
MOVE TO table + (-160 mm, 330 mm, 50 mm)
CONTACT DOWN FORCE 4 N SPEED 10 mm/s TIMEOUT 5 s
"""


def test_a_held_block_pressed_onto_another_settles_at_its_force(tmp_path: Path) -> None:
    """block_b, held, CONTACT DOWN onto block_c at 4 N: done, pressing 4 N within 0.5 N.

    Catches the force loop's integral held off while the push is over its goal: the steel-on-steel
    landing spiked to 19-25 N and the push stayed at 14 N (the joints' friction held the arm at
    rest), "force did not settle within 3 s", on both plants (seeds 0-2 and ideal)."""
    log = tmp_path / "stack.mcap"
    run = run_in_process(write_program(tmp_path, "stack", STACK_B_ON_C), log)
    assert run.returncode == 0, run.describe()
    state = run.log.state
    last = (state.line == 8) & (state.t > state.t[state.line == 8][-1] - 0.1)
    assert abs(float(np.mean(-state.wrench[last, 2])) - 4.0) < 0.5
