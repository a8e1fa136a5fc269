"""A goal motion held short of its goal by an obstacle's field says so (issue 14: outcomes that are true)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import cosmos

GOAL_MM = (600.0, -150.0, 350.0)
BALL_RADIUS_MM = 40.0
GAP_MM = 30.0
"""The ball's surface is this far beside the goal: inside the field's default reach (100 mm)."""


def test_a_goal_in_an_obstacles_field_fails_naming_the_obstacle(tmp_path: Path) -> None:
    """A MOVE TO a point 30 mm beside a ball stops where the ball's field balances the goal's pull,
    more than 1 mm short (read from the log's measured tool point); the failure names the ball and
    the link it holds back. Catches the stall blamed on nothing ("the controller made no progress
    (nothing in the way, ...)"), which it was while the field pushed the wrist away."""
    ball_y = GOAL_MM[1] - BALL_RADIUS_MM - GAP_MM
    program = (
        f"OBSTACLE ball SPHERE AT ({GOAL_MM[0]} mm, {ball_y} mm, {GOAL_MM[2]} mm) "
        f"RADIUS {BALL_RADIUS_MM} mm\n"
        f"MOVE TO ({GOAL_MM[0]} mm, {GOAL_MM[1]} mm, {GOAL_MM[2]} mm)\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(program, log=tmp_path / "held_off.mcap")
    assert not run.ok and run.outcome is not None
    assert run.outcome.span is not None and run.outcome.span.line == 2
    short_mm = np.linalg.norm(run.record.state.x[-1] * 1e3 - np.array(GOAL_MM))
    assert short_mm > 1.0, f"the tool arrived ({short_mm:.2f} mm): nothing to explain"
    assert "cannot reach its goal" in run.outcome.reason, run.outcome.reason
    assert "the field of obstacle 'ball' holds it back (link" in run.outcome.reason, run.outcome.reason
    assert "nothing in the way" not in run.outcome.reason


def test_a_rotation_a_joint_limit_forbids_names_the_joint(tmp_path: Path) -> None:
    """After turns that wind joint 6 to -171 deg, a turn to RPY (180, -45, 90) deg would take it
    past -266 deg (the checker warns so). The limit's potential holds joint 6 back short of it
    (read from the log: 10 deg with the wrist's Coulomb friction compensated at the model's level,
    outside the 8.6 deg margin that counts a joint as at its limit; 7 deg with the arm's level
    learnt, cosmos.osc.friction.adapt_coulomb_error), and the stall was blamed on nothing ("the
    controller made no progress (nothing in the way, no joint at a limit, ...)"). Catches that:
    the failure names joint 6 and its limit, as planned."""
    program = (
        "MOVE TO (550 mm, 0, 400 mm) RPY (180 deg, 0, 0)\n"
        "MOVE TO (550 mm, 0, 400 mm) RPY (180 deg, 0, 179 deg)\n"
        "MOVE TO (600 mm, 50 mm, 380 mm) RPY (180 deg, 0, -60 deg)\n"
        "MOVE TO (600 mm, 50 mm, 380 mm) RPY (135 deg, 0, -60 deg)\n"
        "MOVE TO (550 mm, 0, 400 mm) RPY (180 deg, 45 deg, 0)\n"
        "MOVE TO (550 mm, 0, 400 mm) RPY (180 deg, -45 deg, 90 deg)\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(program, log=tmp_path / "wrist.mcap")
    assert not run.ok and run.outcome is not None
    assert run.outcome.span is not None and run.outcome.span.line == 6
    short_of_limit_deg = np.degrees(run.record.state.q[-1][5]) + 266.0
    assert short_of_limit_deg > 5.0, f"joint 6 ended {short_of_limit_deg:.1f} deg from its limit: at it"
    assert "joint 6 at its limit of -266 deg" in run.outcome.reason, run.outcome.reason
    assert "no progress" not in run.outcome.reason
