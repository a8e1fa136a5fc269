"""The checker foresees a joint limit from the program's text: home pose and static goals."""

from __future__ import annotations

import cosmos

TILT = "MOVE TO (0.55, 0.0, 0.4) RPY (165 deg, -30 deg, 0)\n"


def test_a_goal_a_joint_limit_forbids_is_a_warning_at_its_line() -> None:
    """``RPY (165 deg, -30 deg, 0)`` from tool down runs joint 6 into its 266 deg limit both ways
    round (the run fails there): check warns at the statement and names the configuration in
    which the goal is within range. Catches such a goal passing check silently (it was found
    only at run time, after the arm had moved)."""
    warnings = cosmos.check(TILT).warnings
    assert len(warnings) == 1, warnings
    warning = warnings[0]
    assert (warning.span.line, warning.span.column) == (1, 1)
    assert warning.message.startswith("MOVE TO: joint 6 would reach its limit of 266 deg; "), warning.message
    assert "another configuration of the wrist (joints 4, 5, 6 at " in warning.message


def test_reachable_goals_and_unknown_starts_give_no_warning() -> None:
    """Goals within range from home give none, and after a CONTACT (where the arm ends is not
    known) the same tilt is not foreseen. Catches the warning on every MOVE, and a foresight
    from a pose the program does not fix."""
    assert not cosmos.check("MOVE TO (0.55, 0.0, 0.4)\nMOVE BY (0, 0.1 m, 0)\n").warnings
    after_contact = "MOVE TO table + (0, 0, 20 mm)\nCONTACT DOWN FORCE 5 N\n" + TILT
    assert not [w for w in cosmos.check(after_contact).warnings if "would reach its limit" in w.message]


def test_a_foresight_names_the_pose_it_starts_from() -> None:
    """The tilt from home says so; after a MOVE TO to another point, the same tilt is foreseen
    from that MOVE's goal and says which line's. Catches every foresight worded "from the home
    pose" though the arm starts it where an earlier MOVE left it."""
    (from_home,) = cosmos.check(TILT).warnings
    assert from_home.message.endswith("(from the home pose)"), from_home.message
    (after_move,) = cosmos.check("MOVE TO (0.6, -0.1, 0.35)\n" + TILT).warnings
    assert after_move.span.line == 2
    assert after_move.message.endswith("(from the goal of line 1)"), after_move.message
