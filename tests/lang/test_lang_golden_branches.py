"""Golden plans of the statements issue 22 adds: procedures with parameters, IF/ELSE,
WHILE, TRY/ON FAIL/RETRY, each written out here by hand, field by field.

The values are those the text gives (a parameter's argument in SI, a frame's axis
in the world from the fixture frames of lang_support), not captured from the
compiler. Plans without the new statements are covered by test_lang_golden.py,
which is unchanged.
"""

from __future__ import annotations

import numpy as np
import pytest
from lang_support import compile_text

from cosmos import plan
from cosmos.errors import ProgramError


def test_a_parameter_takes_its_argument_in_si() -> None:
    """``press(12 N, 4 mm)``: the CONTACT holds -12 N on world z, the MOVE goes 4 mm up.
    Catches arguments bound in the wrong order or left in the units written."""
    source = "PROC press(f, lift)\n  CONTACT DOWN FORCE f\n  MOVE BY (0, 0, lift)\nEND\npress(12 N, 4 mm)\n"
    contact_hold, move = compile_text(source).segments[1:]
    np.testing.assert_allclose(contact_hold.force_setpoint, [0, 0, -12.0, 0, 0, 0])
    assert isinstance(move.target, plan.RelativeTarget)
    np.testing.assert_allclose(move.target.offset_world, [0, 0, 0.004])
    assert move.context == "PROC press called at line 5"


def test_arguments_are_evaluated_where_called_and_parameters_are_local() -> None:
    """The argument ``d * 2`` reads the caller's d; after the call the caller's own ``f`` is back,
    and a parameter never leaks out of its call. Catches arguments read in the callee's scope."""
    source = (
        "LET d = 3 mm\nLET f = (0, 0, 50 mm)\nPROC up(f)\n  MOVE BY (0, 0, f)\nEND\nup(d * 2)\nMOVE BY f\n"
    )
    first, second = compile_text(source).segments
    np.testing.assert_allclose(first.target.offset_world, [0, 0, 0.006])  # type: ignore[union-attr]
    np.testing.assert_allclose(second.target.offset_world, [0, 0, 0.05])  # type: ignore[union-attr]
    with pytest.raises(ProgramError, match="unknown name 'h'"):
        compile_text("PROC up(h)\n  MOVE BY (0, 0, h)\nEND\nup(1 mm)\nMOVE BY (0, 0, h)\n")


def test_if_holds_both_branches_with_its_condition_in_the_frame() -> None:
    """``IF FORCE Z < -5 N IN table``: the table frame's Z is world -Z, so the condition reads the
    force along (0, 0, -1); the IF branch holds one MOVE, the ELSE branch another, indexed in
    order. Catches a condition read in the world instead of its frame, or indexes that collide."""
    source = (
        "MOVE TO table + (0, 0, 50 mm)\n"
        "IF FORCE Z < -5 N IN table\n  MOVE BY (0, 0, 10 mm)\n"
        "ELSE\n  MOVE BY (0, 0, 20 mm)\n  WAIT 1 s\nEND\n"
        "WAIT 2 s\n"
    )
    compiled = compile_text(source)
    move, branch, wait = compiled.steps
    assert isinstance(branch, plan.Branch)
    condition = branch.condition
    assert isinstance(condition, plan.Comparison)
    assert condition.quantity is plan.Quantity.FORCE_ALONG
    np.testing.assert_allclose(condition.direction_world, [0, 0, -1])
    assert condition.op is plan.CompareOp.LT and condition.value == pytest.approx(-5.0)
    assert (branch.line, branch.else_line, branch.statement) == (2, 4, "IF FORCE Z < -5 N IN table")
    assert [s.line for s in branch.then_steps] == [3]
    assert [s.line for s in branch.else_steps] == [5, 6]
    assert [s.index for s in compiled.segments] == [0, 1, 2, 3, 4]
    assert [s.line for s in compiled.segments] == [1, 3, 5, 6, 8]
    assert isinstance(wait, plan.Segment) and wait.index == 4 and wait.statement_index == 4


def test_position_and_distance_read_from_the_frame_origin() -> None:
    """``POSITION Y > 5 mm IN hole`` reads along world -Y (the hole frame's Y) from the hole's
    origin; ``DISTANCE < 3 mm IN hole`` from the same origin; LAST FAILED reads the ending.
    Catches a position measured from the world's origin."""
    source = "IF POSITION Y > 5 mm IN hole AND DISTANCE < 3 mm IN hole\n  WAIT 1 s\nEND\n"
    with pytest.raises(ProgramError):  # IN is one clause of the IF, not of each comparison
        compile_text(source)
    source = "IF POSITION Y > 5 mm AND DISTANCE < 3 mm OR LAST FAILED IN hole\n  WAIT 1 s\nEND\n"
    (branch,) = compile_text(source).steps
    assert isinstance(branch, plan.Branch) and isinstance(branch.condition, plan.AnyOf)
    both, last = branch.condition.terms
    assert isinstance(both, plan.AllOf) and isinstance(last, plan.LastOutcome)
    assert last.ending is plan.Ending.FAILED
    position, distance = both.terms
    assert isinstance(position, plan.Comparison) and isinstance(distance, plan.Comparison)
    assert position.quantity is plan.Quantity.POSITION_ALONG
    np.testing.assert_allclose(position.direction_world, [0, -1, 0])
    np.testing.assert_allclose(position.origin_world, [0.6, 0.15, 0.26])
    assert position.value == pytest.approx(0.005)
    assert distance.quantity is plan.Quantity.DISTANCE_FROM and distance.value == pytest.approx(0.003)
    np.testing.assert_allclose(distance.origin_world, [0.6, 0.15, 0.26])


def test_while_holds_one_pass_and_its_bound() -> None:
    """``WHILE ... MAX 7`` compiles its body once; without MAX the bound is 100 passes.
    Catches an unbounded loop."""
    source = "WHILE FORCE < 2 N MAX 7\n  MOVE BY (0, 0, -2 mm)\nEND\nWHILE TORQUE > 1 Nm\n  WAIT 0.5 s\nEND\n"
    first, second = compile_text(source).steps
    assert isinstance(first, plan.Loop) and isinstance(second, plan.Loop)
    assert first.max_passes == 7 and second.max_passes == 100
    assert [s.kind for s in first.body] == [plan.SegmentKind.MOVE]  # type: ignore[union-attr]
    assert isinstance(first.condition, plan.Comparison) and first.condition.quantity is plan.Quantity.FORCE


def test_try_holds_its_block_its_handler_and_the_retry() -> None:
    """TRY's block and ON FAIL part are compiled; RETRY 3 is the handler's last step.
    Catches a handler dropped from the plan or indexes reused after it."""
    source = (
        "TRY\n  INSERT DOWN DEPTH 10 mm FORCE 5 N\nON FAIL\n  MOVE BY (0, 0, 10 mm)\n  RETRY 3\nEND\n"
        "MOVE BY (0, 0, 5 mm)\n"
    )
    attempt, after = compile_text(source).steps
    assert isinstance(attempt, plan.Attempt)
    assert (attempt.line, attempt.handler_line) == (1, 3)
    # No contact is held: the INSERT approaches with every axis held, then inserts.
    assert [s.kind for s in attempt.body] == [  # type: ignore[union-attr]
        plan.SegmentKind.CONTACT_APPROACH,
        plan.SegmentKind.INSERT,
    ]
    move, retry = attempt.handler
    assert isinstance(move, plan.Segment) and isinstance(retry, plan.Retry)
    assert retry.times == 3 and retry.line == 5
    assert isinstance(after, plan.Segment) and after.index == 3


def test_names_and_settings_made_in_a_branch_end_with_it() -> None:
    """SPEED inside an IF applies to its branch only; the MOVE after END has the speed before.
    Catches a branch's setting leaking into statements compiled for both branches."""
    source = (
        "SPEED 0.2 m/s\nIF FORCE > 1 N\n  SPEED 0.05 m/s\n  MOVE BY (0, 0, 1 mm)\nEND\nMOVE BY (0, 0, 1 mm)\n"
    )
    inner, outer = compile_text(source).segments
    assert inner.speed_limit_mps == pytest.approx(0.05)
    assert outer.speed_limit_mps == pytest.approx(0.2)


def test_a_contact_made_in_both_branches_is_held_after() -> None:
    """Both branches make the same contact: the SLIDE after END slides on it (-8 N on z).
    Catches a merge that forgets the contact both branches hold."""
    source = (
        "IF FORCE > 1 N\n  CONTACT DOWN FORCE 8 N\n"
        "ELSE\n  MOVE BY (0, 0, -5 mm)\n  CONTACT DOWN FORCE 8 N\nEND\n"
        "SLIDE +X BY 20 mm\n"
    )
    slide = compile_text(source).segments[-1]
    assert slide.kind is plan.SegmentKind.SLIDE
    np.testing.assert_allclose(slide.force_setpoint, [0, 0, -8.0, 0, 0, 0])


def test_json_holds_the_branches() -> None:
    """The plan's JSON nests the branches under their IF. Catches a branch missing from --json."""
    compiled = compile_text("IF LAST STOPPED\n  WAIT 1 s\nELSE\n  WAIT 2 s\nEND\n")
    (step,) = plan.plan_to_json(compiled)["steps"]
    assert step["step"] == "if" and step["condition"] == {"last": "stopped", "text": "LAST STOPPED"}
    assert [s["completion"]["duration_s"] for s in step["then"] + step["else"]] == [1.0, 2.0]
