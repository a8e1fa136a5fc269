"""How a failed statement is named: its head, then the reason (cosmos.execution.wording)."""

from __future__ import annotations

import pytest

from cosmos.execution.wording import failure_text


@pytest.mark.parametrize(
    ("statement", "reason", "said"),
    [
        ("CONTACT UP FORCE 5 N", "found no contact within 1.5 s", "CONTACT UP found no contact within 1.5 s"),
        ("WAIT 2 s", "timed out", "WAIT 2 s timed out"),
        ("MOVE BY (0, 0, -5 mm)", "protective stop: tool hit", "MOVE BY: protective stop: tool hit"),
        # Read "GRASP FORCE closed to 0 mm ..." (FORCE is a clause, not what is grasped).
        ("GRASP FORCE 40 N", "closed to 0 mm: nothing", "GRASP closed to 0 mm: nothing"),
        ("GRASP peg FORCE 80 N", "closed to 0 mm: nothing", "GRASP peg closed to 0 mm: nothing"),
        # Read "RELEASE the gripper holds nothing" and "WAIT 0.1 s the POSTURE of line 2 ...".
        ("RELEASE", "the gripper holds nothing", "RELEASE: the gripper holds nothing"),
        ("WAIT 0.1 s", "the POSTURE of line 2 gives 5", "WAIT 0.1 s: the POSTURE of line 2 gives 5"),
        ("WAIT UNTIL FORCE > 5 N", "timed out after 30 s", "WAIT UNTIL timed out after 30 s"),
    ],
)
def test_a_failure_reads_as_its_head_then_its_reason(statement: str, reason: str, said: str) -> None:
    """Catches messages that ran a statement's head into a reason with a subject of its own."""
    assert failure_text(statement, reason) == said
