"""The fingers in ``/cosmos/state``: a gripper's log has them, a peg's log is as before."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader

from cosmos.runlog.reader import read_log
from tests.hand.gripper_support import hand_samples
from tests.run.run_support import PROGRAMS, run_in_process, write_program
from tests.runlog.runlog_schema_check import validate

BLOCK_WIDTH_M = 0.040
"""The block's size between the pads (its OBJECT line below)."""
GRIP_N = 40.0
PROGRAM = """TOOL GRIPPER
OBJECT block BOX SIZE (40 mm, 30 mm, 50 mm) MASS 0.5 kg AT table
MOVE TO table + (0, 0, 32.5 mm) SPEED 0.2 m/s
GRASP block FORCE 40 N WIDTH 40 mm
MOVE BY (0, 0, 30 mm) SPEED 0.1 m/s
"""


def _state_messages(log: Path) -> tuple[list[dict[str, object]], dict[str, object]]:
    """The log's /cosmos/state messages as JSON, and their channel's schema."""
    with open(log, "rb") as stream:
        messages = [
            (json.loads(message.data), json.loads(schema.data))
            for schema, channel, message in make_reader(stream).iter_messages(topics=["/cosmos/state"])
        ]
    return [m for m, _ in messages], messages[0][1]


@pytest.mark.parametrize("ideal", [False, True], ids=["realistic", "ideal"])
def test_state_has_the_fingers_of_a_gripper_run(tmp_path: Path, ideal: bool) -> None:
    """While the 40 mm block is held, the state's two finger positions add up to 40 mm and both
    pads read 40 N +- 10 %; every state message validates against its channel's schema; at the
    /cosmos/hand samples the state has the same pads' forces (one reading for both).

    Catches: finger fields missing or misplaced in the state row (the reader would split the
    wrench into them), positions that are not each pad's (their sum not the block's width),
    forces from the wrong pad or a stale staging row, a schema that rejects its own messages.
    """
    log = tmp_path / "fs.mcap"
    run = run_in_process(write_program(tmp_path, "fs", PROGRAM), log, ideal=ideal)
    assert run.returncode == 0, run.describe()
    messages, schema = _state_messages(log)
    assert all(validate(m, schema) == [] for m in messages)
    record = read_log(log)
    assert record.metadata.get("fingers") == "2"
    state = record.state
    assert state.fingers is not None and state.finger_force is not None
    lifted = run.events("start", 5)[0].t
    held = (state.t > lifted + 0.05) & (state.t < run.events("done", 5)[0].t)
    assert held.sum() > 20
    opening = state.fingers[held].sum(axis=1)
    assert np.all(np.abs(opening - BLOCK_WIDTH_M) < 0.002), (opening.min(), opening.max())
    assert np.all(np.abs(state.finger_force[held] - GRIP_N) <= 0.1 * GRIP_N)
    # Before the GRASP the fingers are open and the pads feel nothing.
    before = state.t < run.events("start", 4)[0].t
    assert np.all(state.fingers[before].sum(axis=1) > 0.06) and np.all(np.abs(state.finger_force[before]) < 1)
    by_time = {round(float(t), 6): row for t, row in zip(state.t, state.finger_force, strict=True)}
    for sample in hand_samples(log):
        row = by_time[round(float(sample["t"]), 6)]  # type: ignore[arg-type]
        assert abs(row[0] - float(sample["force_left"])) < 1e-3  # type: ignore[arg-type]
        assert abs(row[1] - float(sample["force_right"])) < 1e-3  # type: ignore[arg-type]


def test_peg_log_state_is_as_before(tmp_path: Path) -> None:
    """A peg run's state has no finger fields, no ``fingers`` metadata, and its schema's fields
    are exactly the arm's.

    Catches: the gripper's fields leaking into every log (old readers and the published schema
    of a peg run would no longer match).
    """
    log = tmp_path / "hello.mcap"
    run = run_in_process(PROGRAMS / "hello.cos", log, ideal=True)
    assert run.returncode == 0, run.describe()
    messages, schema = _state_messages(log)
    arm = ["t", "q", "qd", "tau", "x", "quat", "v", "wrench", "segment", "line"]
    assert sorted(schema["properties"]) == sorted(arm)  # type: ignore[call-overload]
    assert all(list(m) == arm for m in messages)
    record = read_log(log)
    assert "fingers" not in record.metadata
    assert record.state.fingers is None and record.state.finger_force is None
