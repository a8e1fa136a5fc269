"""The protective stops see the gripper's fingers and the workcell's objects (issue 14, item 6)."""

from __future__ import annotations

import warnings
from pathlib import Path

import cosmos

ONTO_THE_CAN = """\
TOOL GRIPPER
OBJECT can CYLINDER RADIUS 25 mm HEIGHT 80 mm MASS 0.3 kg AT table + (0, -100 mm, 0)
MOVE TO table + (0, -100 mm, 150 mm)
MOVE TO table + (0, -100 mm, 30 mm) SPEED 40 mm/s
"""


def test_a_free_move_that_drives_the_hand_onto_an_object_is_a_collision(tmp_path: Path) -> None:
    """Lowering the open hand over an 80 mm can to 30 mm above its base drives the palm onto the
    can's top: a contact stop naming the can, with a ``collision`` event. Catches contacts of the
    hand and the objects ignored by the supervision (the run went on until the wrist's force limit
    tripped at 117.6 N, its message naming nothing), and a held object's fingers taken for one."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(ONTO_THE_CAN, log=tmp_path / "onto_the_can.mcap")
    assert not run.ok and run.outcome is not None
    assert run.outcome.span is not None and run.outcome.span.line == 4
    assert run.outcome.reason.startswith("protective stop: tool hit object 'can' at "), run.outcome.reason
    collisions = [e.reason for e in run.events if e.kind == "collision"]
    assert collisions == ["tool touches can"], collisions
    assert run.record.state.x[-1, 2] > 0.2 + 0.030, run.record.state.x[-1]  # held above its goal
