"""``cosmos repl --tool gripper``: a session with the gripper's workcell; TOOL and OBJECT typed
into a session cannot change the plant it was built with, and say so."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from cosmos.cli import cli
from cosmos.repl.app import ReplApp
from cosmos.runlog.reader import read_log
from tests.hand.gripper_support import tf_last_pose

BLOCK_B_CENTRE_M = np.array([0.44, 0.10, 0.215])
"""block_b's centre where the docs put it: base (440, 100, 200) mm, 30 mm tall."""
PICK_B = (
    "TOOL GRIPPER\n"
    "OBJECT cup CYLINDER RADIUS 30 mm HEIGHT 80 mm MASS 0.2 kg AT table\n"
    "MOVE TO table + (-160 mm, 250 mm, 100 mm) SPEED 0.2 m/s\n"
    "MOVE TO table + (-160 mm, 250 mm, 12.5 mm) SPEED 50 mm/s\n"
    "GRASP block_b FORCE 30 N WIDTH 30 mm\n"
    "MOVE BY (0, 0, 50 mm) SPEED 0.1 m/s UNTIL FINGER FORCE < 5 N\n"
)


def test_repl_tool_gripper_session_grasps_a_block(tmp_path: Path) -> None:
    """Through the CLI's --tool gripper: TOOL GRIPPER is accepted, GRASP block_b lifts it, the
    log is a gripper's (metadata, fingers in the state); OBJECT is refused with the reason.

    Catches: the bug this flag fixes (a REPL's TOOL GRIPPER left the peg on, so GRASP failed),
    a session whose compiler does not know the workcell's objects, and an OBJECT that compiles
    but never appears in the plant.
    """
    log = tmp_path / "g.mcap"
    result = CliRunner().invoke(cli, ["repl", "--tool", "gripper", "--log", str(log)], input=PICK_B)
    assert result.exit_code == 0, result.output
    assert "must be chosen" not in result.output
    assert "declare it in a program and cosmos run it" in result.output
    record = read_log(log)
    assert record.metadata["tool"] == "gripper" and record.state.fingers is not None
    position, _ = tf_last_pose(log, "block_b")
    assert np.linalg.norm(position - (BLOCK_B_CENTRE_M + [0.0, 0.0, 0.05])) < 0.003, position
    assert not [e for e in record.events if e.kind == "failed"], record.events


def test_repl_tool_typed_into_a_peg_session_names_the_flag(tmp_path: Path) -> None:
    """Catches: TOOL GRIPPER accepted by a peg session (a GRASP then fails on a hand it lacks)."""
    out = io.StringIO()
    app = ReplApp(tmp_path / "p.mcap", out, stdin=io.StringIO("TOOL GRIPPER\nGRASP\n"))
    app.run()
    text = out.getvalue()
    assert "TOOL must be chosen when the session starts: cosmos repl --tool gripper" in text
    assert "<repl>:1:1: TOOL must be chosen" in text
    assert read_log(tmp_path / "p.mcap").metadata.get("tool", "peg") == "peg"
