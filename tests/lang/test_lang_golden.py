"""Golden tests: each statement form of the language contract compiles to the plan
written out here by hand, field by field (selection axes, setpoints, frames,
targets, completions).

The forms are those of the contract (docs/language.md and the project's
reference page); ``test_every_contract_example_is_covered`` checks that no
example of the reference page is missing here.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from lang_support import (
    DOWN_FACING,
    FIXTURE_ROTATION,
    FIXTURES,
    SLOPE_ROTATION,
    compile_text,
    segments_after,
    steps_after,
)

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import compile_program

I3 = np.eye(3)
ALL_MOTION = [1, 1, 1, 1, 1, 1]
NONE6 = (None,) * 6
ZERO6 = [0.0] * 6
PRELUDE = "LET p = (0.5, 0.1, 0.4)\nLET a = (0.45, 0, 0.45)\nLET b = (0.5, 0.05, 0.42)\nSPEED 0.25 m/s\n"
CONTACT_DOWN = PRELUDE + "CONTACT DOWN FORCE 8 N\n"
GOAL = {"type": plan.GoalReached, "position_tolerance_m": 1e-3, "orientation_tolerance_rad": 0.0175}


def check(segment: plan.Segment, **expected: Any) -> None:
    """Compare the named fields of a segment with hand-written values."""
    for field, value in expected.items():
        actual = getattr(segment, field)
        where = f"{segment.statement!r} [{segment.kind.value}] .{field}"
        if field == "motion_axes":
            assert [int(a) for a in actual] == value, where
        elif field in ("force_setpoint", "frame_rotation"):
            np.testing.assert_allclose(actual, value, atol=1e-12, err_msg=where)
        elif field in ("target", "completion", "until", "jam_check", "search"):
            check_object(actual, value, where)
        elif field == "via":
            assert len(actual) == len(value), where
            for got, want in zip(actual, value, strict=True):
                check_object(got, want, where)
        elif isinstance(value, float):
            assert actual == pytest.approx(value), where
        else:
            assert actual == value, where


def check_object(actual: Any, expected: Any, where: str) -> None:
    if expected is None:
        assert actual is None, where
        return
    expected = dict(expected)
    assert isinstance(actual, expected.pop("type")), where
    for name, value in expected.items():
        got = getattr(actual, name)
        if isinstance(value, dict):
            check_object(got, value, f"{where}.{name}")
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            assert len(got) == len(value), where
            for g, v in zip(got, value, strict=True):
                check_object(g, v, f"{where}.{name}")
        elif value is None:
            assert got is None, f"{where}.{name}"
        elif isinstance(value, list | np.ndarray):
            np.testing.assert_allclose(got, value, atol=1e-12, err_msg=f"{where}.{name}")
        elif isinstance(value, float):
            assert got == pytest.approx(value), f"{where}.{name}"
        else:
            assert got == value, f"{where}.{name}"


def absolute(position: list[float], rotation: Any = None) -> dict[str, Any]:
    return {"type": plan.AbsoluteTarget, "position_world": position, "rotation_world": rotation}


def relative(offset: list[float]) -> dict[str, Any]:
    return {"type": plan.RelativeTarget, "offset_world": offset}


# ------------------------------------------------------------------------ MOVE


def test_move_to_a_named_position_keeps_orientation() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO p")
    check(
        segment,
        kind=plan.SegmentKind.MOVE,
        frame_name="world",
        frame_rotation=I3,
        motion_axes=ALL_MOTION,
        force_setpoint=ZERO6,
        stiffness=NONE6,
        damping=NONE6,
        target=absolute([0.5, 0.1, 0.4], None),
        via=[],
        speed_limit_mps=0.25,
        duration_s=None,
        completion=GOAL,
        until=None,
        timeout_s=None,
        jam_check=None,
        statement="MOVE TO p",
        line=1,
    )


def test_move_speed_clause_overrides_the_default() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO p SPEED 0.1 m/s")
    check(segment, speed_limit_mps=0.1, duration_s=None, target=absolute([0.5, 0.1, 0.4]))


def test_move_by_is_relative_in_the_world() -> None:
    [segment] = segments_after(PRELUDE, "MOVE BY (0, 0, -50 mm)")
    check(segment, kind=plan.SegmentKind.MOVE, target=relative([0, 0, -0.05]), speed_limit_mps=0.25)


def test_move_via_passes_intermediate_goals_in_order() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO p VIA a, b")
    check(
        segment,
        target=absolute([0.5, 0.1, 0.4]),
        via=[absolute([0.45, 0, 0.45]), absolute([0.5, 0.05, 0.42])],
        via_radius_m=0.01,
    )


def test_move_in_a_duration_is_timed_without_speed_limit() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO p IN 2 s")
    check(segment, duration_s=2.0, speed_limit_mps=None, target=absolute([0.5, 0.1, 0.4]))


def test_move_to_a_fixture_offset_takes_the_fixture_orientation() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO hole + (0, 0, 80 mm)")
    check(segment, target=absolute([0.6, 0.15, 0.34], DOWN_FACING))


def test_move_to_a_bare_position_keeps_orientation() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO (0.5, 0.1, 0.4)")
    check(segment, target=absolute([0.5, 0.1, 0.4], None))


def test_components_carry_their_own_units() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO (500 mm, 100 mm, 0.3 m)")
    check(segment, target=absolute([0.5, 0.1, 0.3]))


def test_pose_roll_180_deg_turns_z_down() -> None:
    [segment] = segments_after(PRELUDE, "MOVE TO (0.5, 0.1, 0.3) RPY (180 deg, 0, 0)")
    check(segment, target=absolute([0.5, 0.1, 0.3], DOWN_FACING))


def test_rpy_is_about_fixed_world_axes_x_then_y_then_z() -> None:
    # Roll 90 deg about world x, then yaw 90 deg about world z: the frame's x axis
    # (untouched by the roll) ends on world y; its y axis (taken to world z by the
    # roll) stays on z.
    [segment] = segments_after(PRELUDE, "MOVE TO (0.5, 0.1, 0.3) RPY (90 deg, 0, 90 deg)")
    assert isinstance(segment.target, plan.AbsoluteTarget)
    rotation = segment.target.rotation_world
    np.testing.assert_allclose(rotation[:, 0], [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(rotation[:, 1], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(rotation[:, 2], [1, 0, 0], atol=1e-12)


def test_frame_definition_and_offset_along_world_axes() -> None:
    prelude = "FRAME hole = (0.55, 0.10, 0.02) RPY (180 deg, 0, 0)\n"
    [segment] = segments_after(prelude, "MOVE TO hole + (0, 0, 100 mm)")
    check(segment, target=absolute([0.55, 0.1, 0.12], DOWN_FACING))


def test_let_speed_then_speed_statement() -> None:
    [segment] = segments_after("LET speed = 0.2 m/s\nSPEED speed\n", "MOVE BY (0, 0, 10 mm)")
    check(segment, speed_limit_mps=0.2)


def test_speed_statement_sets_the_default_for_what_follows() -> None:
    segments = compile_text("MOVE BY (0, 0, 1 mm)\nSPEED 0.3 m/s\nMOVE BY (0, 0, 1 mm)\n").segments
    assert [s.speed_limit_mps for s in segments] == [0.1, 0.3]


def test_robot_chooses_the_arm_and_compiles_to_nothing() -> None:
    """Catches ROBOT emitting a step, the plan losing its arm, or the PUMA not being the default."""
    chosen = compile_text("ROBOT panda\nMOVE BY (0, 0, 10 mm)\n")
    plain = compile_text("MOVE BY (0, 0, 10 mm)\n")
    assert (chosen.robot, plain.robot) == ("panda", "puma560")
    [segment] = chosen.segments
    check(segment, line=2, target=relative([0, 0, 0.01]))
    assert compile_text("# the arm\nROBOT PUMA560\n").robot == "puma560"  # names fold case


def test_a_run_on_one_arm_refuses_a_program_for_the_other() -> None:
    """``cosmos run --robot puma560`` of a ROBOT panda program: catches the program's word winning."""
    with pytest.raises(ProgramError, match=r"ROBOT panda: this run is on the puma560 \(--robot\)"):
        compile_program("ROBOT panda\n", "test.cos", FIXTURES, robot="puma560")
    assert compile_program("MOVE BY (0, 0, 1 mm)\n", "test.cos", FIXTURES, robot="panda").robot == "panda"


def test_move_by_in_a_frame_is_along_its_axes() -> None:
    [segment] = segments_after(PRELUDE, "MOVE BY (0, 0, 10 mm) IN hole")
    check(segment, frame_name="hole", frame_rotation=DOWN_FACING, target=relative([0, 0, -0.01]))


# --------------------------------------------------------------------- CONTACT


def test_contact_down_is_an_approach_then_a_force_hold() -> None:
    approach, hold = segments_after(PRELUDE, "CONTACT DOWN FORCE 10 N")
    common = {"frame_rotation": I3, "statement": "CONTACT DOWN FORCE 10 N", "statement_index": 0}
    check(
        approach,
        kind=plan.SegmentKind.CONTACT_APPROACH,
        motion_axes=ALL_MOTION,
        force_setpoint=ZERO6,
        stiffness=NONE6,
        target=relative([0, 0, -0.3]),
        speed_limit_mps=0.02,
        completion={
            "type": plan.ContactTouch,
            "direction_world": [0, 0, -1],
            "threshold_n": 2.0,
            "max_travel_m": 0.3,
        },
        **common,
    )
    check(
        hold,
        kind=plan.SegmentKind.CONTACT_HOLD,
        motion_axes=[1, 1, 0, 1, 1, 1],
        # the tool presses down on the table: -10 N along world z
        force_setpoint=[0, 0, -10, 0, 0, 0],
        stiffness=(None, None, 0.0, None, None, None),
        target=None,
        speed_limit_mps=0.02,
        completion={
            "type": plan.ForceSettled,
            "tolerance_n": 1.0,
            "settle_time_s": 0.2,
            "max_time_s": 3.0,
        },
        **common,
    )


def test_contact_in_a_frame_with_all_clauses() -> None:
    line = "CONTACT -X IN fixture FORCE 5 N SPEED 10 mm/s TIMEOUT 4 s"
    approach, hold = segments_after(PRELUDE, line)
    # fixture x is world +y (Rz 90 deg), so -X IN fixture is world -y
    for segment in (approach, hold):
        check(
            segment,
            frame_name="fixture",
            frame_rotation=FIXTURE_ROTATION,
            speed_limit_mps=0.01,
            timeout_s=4.0,
        )
    check(
        approach,
        motion_axes=ALL_MOTION,
        target=relative([0, -0.3, 0]),
        completion={"type": plan.ContactTouch, "direction_world": [0, -1, 0], "threshold_n": 2.0},
    )
    check(
        hold,
        motion_axes=[0, 1, 1, 1, 1, 1],
        force_setpoint=[-5, 0, 0, 0, 0, 0],
        stiffness=(0.0, None, None, None, None, None),
        completion={"type": plan.ForceSettled, "tolerance_n": 0.5},
    )


def test_small_contact_force_lowers_the_touch_threshold() -> None:
    approach, _ = segments_after(PRELUDE, "CONTACT DOWN FORCE 3 N")
    check(approach, completion={"type": plan.ContactTouch, "threshold_n": 1.5})


def test_contact_square_onto_the_slope() -> None:
    approach, hold = segments_after(PRELUDE, "CONTACT +Z IN slope FORCE 5 N")
    check(
        approach,
        frame_rotation=SLOPE_ROTATION,
        completion={"type": plan.ContactTouch, "direction_world": SLOPE_ROTATION[:, 2]},
        target=relative(list(SLOPE_ROTATION[:, 2] * 0.3)),
    )
    check(hold, motion_axes=[1, 1, 0, 1, 1, 1], force_setpoint=[0, 0, 5, 0, 0, 0])


# ----------------------------------------------------------------------- SLIDE


def test_slide_keeps_the_contact_axis_force_controlled_at_its_own_force() -> None:
    [segment] = segments_after(CONTACT_DOWN, "SLIDE +X BY 100 mm FORCE 10 N")
    check(
        segment,
        kind=plan.SegmentKind.SLIDE,
        frame_rotation=I3,
        motion_axes=[1, 1, 0, 1, 1, 1],
        force_setpoint=[0, 0, -10, 0, 0, 0],
        stiffness=(None, None, 0.0, None, None, None),
        target=relative([0.1, 0, 0]),
        speed_limit_mps=0.25,
        completion=GOAL,
    )


def test_slide_without_force_uses_the_contact_force() -> None:
    [segment] = segments_after(CONTACT_DOWN, "SLIDE +Y BY 50 mm SPEED 20 mm/s")
    check(
        segment,
        motion_axes=[1, 1, 0, 1, 1, 1],
        force_setpoint=[0, 0, -8, 0, 0, 0],
        target=relative([0, 0.05, 0]),
        speed_limit_mps=0.02,
    )


def test_slide_force_lasts_for_that_slide_only() -> None:
    slide, wait = compile_text("CONTACT DOWN FORCE 8 N\nSLIDE +X BY 10 mm FORCE 12 N\nWAIT 1 s\n").segments[
        2:
    ]
    np.testing.assert_allclose(slide.force_setpoint, [0, 0, -12, 0, 0, 0])
    np.testing.assert_allclose(wait.force_setpoint, [0, 0, -8, 0, 0, 0])


def test_slide_on_the_slope_in_its_frame() -> None:
    [segment] = segments_after(PRELUDE + "CONTACT +Z IN slope FORCE 5 N\n", "SLIDE +X IN slope BY 20 mm")
    check(
        segment,
        frame_rotation=SLOPE_ROTATION,
        motion_axes=[1, 1, 0, 1, 1, 1],
        force_setpoint=[0, 0, 5, 0, 0, 0],
        target=relative(list(SLOPE_ROTATION[:, 0] * 0.02)),
    )


# ---------------------------------------------------------------------- INSERT


def test_insert_down_complies_laterally_by_default() -> None:
    [segment] = segments_after(CONTACT_DOWN, "INSERT DOWN DEPTH 30 mm FORCE 15 N")
    check(
        segment,
        kind=plan.SegmentKind.INSERT,
        frame_rotation=I3,
        motion_axes=[0, 0, 0, 0, 0, 1],
        force_setpoint=[0, 0, -15, 0, 0, 0],
        stiffness=(0.0, 0.0, 0.0, 0.0, 0.0, None),
        target=None,
        speed_limit_mps=0.02,
        completion={"type": plan.DepthReached, "direction_world": [0, 0, -1], "depth_m": 0.03},
        jam_check={"type": plan.JamCheck, "stall_speed_mps": 5e-4, "stall_time_s": 1.0},
        timeout_s=None,
    )


def test_insert_in_the_hole_frame_with_explicit_comply() -> None:
    line = "INSERT -Z IN hole DEPTH 25 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s"
    steps, warnings = steps_after(CONTACT_DOWN, line)
    [segment] = steps
    assert isinstance(segment, plan.Segment)
    # hole z points into the hole (world -z), so -Z IN hole pushes up, out of it
    check(
        segment,
        frame_name="hole",
        frame_rotation=DOWN_FACING,
        motion_axes=[0, 0, 0, 0, 0, 1],
        force_setpoint=[0, 0, -15, 0, 0, 0],
        completion={"type": plan.DepthReached, "direction_world": [0, 0, 1], "depth_m": 0.025},
        timeout_s=10.0,
    )
    assert any("moves away from it" in w.message for w in warnings)


def test_insert_across_a_held_contact_keeps_the_contact_force() -> None:
    [segment] = segments_after(CONTACT_DOWN, "INSERT +X DEPTH 10 mm FORCE 4 N")
    # default compliance: across X, minus the contact's axis Z: Y and RY RZ
    check(
        segment,
        motion_axes=[0, 0, 0, 1, 0, 0],
        force_setpoint=[4, 0, -8, 0, 0, 0],
    )


def test_insert_comply_none_keeps_lateral_axes_stiff() -> None:
    [segment] = segments_after(CONTACT_DOWN, "INSERT DOWN DEPTH 5 mm FORCE 10 N COMPLY NONE")
    check(segment, motion_axes=[1, 1, 0, 1, 1, 1], force_setpoint=[0, 0, -10, 0, 0, 0])


def test_insert_search_spiral_moves_the_lateral_translations() -> None:
    line = "INSERT DOWN DEPTH 25 mm FORCE 15 N SEARCH SPIRAL RADIUS 20 mm PITCH 6 mm TIMEOUT 30 s"
    [segment] = segments_after(CONTACT_DOWN, line)
    check(
        segment,
        kind=plan.SegmentKind.INSERT,
        motion_axes=[0, 0, 0, 0, 0, 1],  # the search's pattern is the executor's, not the plan's axes
        force_setpoint=[0, 0, -15, 0, 0, 0],
        completion={"type": plan.DepthReached, "direction_world": [0, 0, -1], "depth_m": 0.025},
        search={
            "type": plan.Search,
            "pattern": plan.SearchPattern.SPIRAL,
            "radius_m": 0.02,
            "pitch_m": 0.006,
            "lateral_axes": (0, 1),
            "speed_mps": 0.01,
            "found_depth_m": 0.001,
        },
    )


def test_insert_search_lissajous_across_an_x_insertion() -> None:
    prelude = PRELUDE + "CONTACT +X FORCE 5 N\n"
    [segment] = segments_after(
        prelude, "INSERT +X DEPTH 10 mm FORCE 5 N SEARCH LISSAJOUS PITCH 2 mm RADIUS 5 mm"
    )
    check(
        segment,
        search={
            "type": plan.Search,
            "pattern": plan.SearchPattern.LISSAJOUS,
            "radius_m": 0.005,
            "pitch_m": 0.002,
            "lateral_axes": (1, 2),
        },
    )


def test_insert_search_warns_of_a_timeout_shorter_than_its_pattern() -> None:
    """The spiral of 20 mm at pitch 6 mm is pi 20^2 / 6 ~ 209 mm long: 21 s at 10 mm/s plus its
    ramps. Catches a warning that misjudges the pattern's time (or is never given)."""
    search = "INSERT DOWN DEPTH 25 mm FORCE 15 N SEARCH SPIRAL RADIUS 20 mm PITCH 6 mm"
    _, warnings = steps_after(CONTACT_DOWN, search + " TIMEOUT 20 s")
    assert any("before its SEARCH SPIRAL has covered its RADIUS" in w.message for w in warnings)
    _, warnings = steps_after(CONTACT_DOWN, search + " TIMEOUT 22 s")
    assert not any("SEARCH" in w.message for w in warnings)


def test_insert_without_search_has_none() -> None:
    [segment] = segments_after(CONTACT_DOWN, "INSERT DOWN DEPTH 30 mm FORCE 15 N")
    assert segment.search is None


# ------------------------------------------------------------ COMPLY and WAIT


def test_comply_without_stiffness_is_zero_force_control() -> None:
    [segment] = segments_after(PRELUDE + "COMPLY X Y\n", "MOVE BY (0, 0, 10 mm)")
    check(
        segment,
        motion_axes=[0, 0, 1, 1, 1, 1],
        force_setpoint=ZERO6,
        stiffness=(0.0, 0.0, None, None, None, None),
    )


def test_comply_with_rotational_stiffness_makes_springs() -> None:
    [segment] = segments_after(PRELUDE + "COMPLY RX RY STIFFNESS 5 Nm/rad\n", "MOVE BY (0, 0, 10 mm)")
    check(segment, motion_axes=ALL_MOTION, stiffness=(None, None, None, 5.0, 5.0, None))


def test_comply_with_translational_stiffness_and_damping() -> None:
    prelude = PRELUDE + "COMPLY X STIFFNESS 200 N/m DAMPING 20 N s/m\n"
    [segment] = segments_after(prelude, "MOVE BY (0, 0, 10 mm)")
    check(segment, motion_axes=ALL_MOTION, stiffness=(200.0, None, None, None, None, None))
    check(segment, damping=(20.0, None, None, None, None, None))


def test_comply_none_restores_full_stiffness() -> None:
    [segment] = segments_after(PRELUDE + "COMPLY X Y\nCOMPLY X STIFFNESS 200 N/m\nCOMPLY NONE\n", "MOVE TO p")
    check(segment, motion_axes=ALL_MOTION, stiffness=NONE6, damping=NONE6)


def test_comply_statements_add_up() -> None:
    [segment] = segments_after(PRELUDE + "COMPLY X\nCOMPLY RZ STIFFNESS 2 Nm/rad\n", "MOVE TO p")
    check(segment, motion_axes=[0, 1, 1, 1, 1, 1], stiffness=(0.0, None, None, None, None, 2.0))


def test_wait_holds_still_without_contact() -> None:
    [segment] = segments_after(PRELUDE, "WAIT 2 s")
    check(
        segment,
        kind=plan.SegmentKind.WAIT,
        motion_axes=ALL_MOTION,
        force_setpoint=ZERO6,
        target=None,
        speed_limit_mps=None,
        completion={"type": plan.Elapsed, "duration_s": 2.0},
    )


def test_wait_keeps_holding_the_contact_in_its_frame() -> None:
    [segment] = segments_after(PRELUDE + "CONTACT -X IN fixture FORCE 5 N\n", "WAIT 1.5 s")
    check(
        segment,
        frame_name="fixture",
        frame_rotation=FIXTURE_ROTATION,
        motion_axes=[0, 1, 1, 1, 1, 1],
        force_setpoint=[-5, 0, 0, 0, 0, 0],
        speed_limit_mps=0.02,
        completion={"type": plan.Elapsed, "duration_s": 1.5},
    )


def test_move_releases_the_contact() -> None:
    [segment] = segments_after(CONTACT_DOWN, "MOVE BY (0, 0, 100 mm)")
    check(segment, motion_axes=ALL_MOTION, force_setpoint=ZERO6, target=relative([0, 0, 0.1]))
    [wait] = segments_after(CONTACT_DOWN + "MOVE BY (0, 0, 100 mm)\n", "WAIT 1 s")
    check(wait, motion_axes=ALL_MOTION, force_setpoint=ZERO6)


def test_contact_in_another_direction_replaces_the_held_contact() -> None:
    [wait] = segments_after(CONTACT_DOWN + "CONTACT +Y FORCE 3 N\n", "WAIT 1 s")
    check(wait, motion_axes=[1, 0, 1, 1, 1, 1], force_setpoint=[0, 3, 0, 0, 0, 0])


# ----------------------------------------------------------------------- UNTIL


def comparison(quantity: plan.Quantity, op: str, value: float, direction: Any = None) -> dict[str, Any]:
    return {
        "type": plan.Comparison,
        "quantity": quantity,
        "op": plan.CompareOp(op),
        "value": value,
        "direction_world": direction,
    }


@pytest.mark.parametrize(
    ("condition", "expected"),
    [
        ("FORCE > 5 N", comparison(plan.Quantity.FORCE, ">", 5.0)),
        ("FORCE Z < -3 N", comparison(plan.Quantity.FORCE_ALONG, "<", -3.0, [0, 0, 1])),
        ("FORCE -Z > 3 N", comparison(plan.Quantity.FORCE_ALONG, ">", 3.0, [0, 0, -1])),
        ("DISTANCE > 40 mm", comparison(plan.Quantity.DISTANCE, ">", 0.04)),
        ("TORQUE RZ >= 0.5 Nm", comparison(plan.Quantity.TORQUE_ABOUT, ">=", 0.5, [0, 0, 1])),
        ("TORQUE > 1 Nm", comparison(plan.Quantity.TORQUE, ">", 1.0)),
        (
            "DISTANCE > 40 mm AND FORCE > 5 N OR (FORCE Z < -3 N)",
            {
                "type": plan.AnyOf,
                "terms": [
                    {
                        "type": plan.AllOf,
                        "terms": [
                            comparison(plan.Quantity.DISTANCE, ">", 0.04),
                            comparison(plan.Quantity.FORCE, ">", 5.0),
                        ],
                    },
                    comparison(plan.Quantity.FORCE_ALONG, "<", -3.0, [0, 0, 1]),
                ],
            },
        ),
    ],
)
def test_until_conditions(condition: str, expected: dict[str, Any]) -> None:
    [segment] = segments_after(PRELUDE, f"MOVE BY (0, 0, -100 mm) UNTIL {condition} TIMEOUT 5 s")
    check(segment, until=expected, timeout_s=5.0)


def test_until_axes_are_those_of_the_task_frame() -> None:
    approach, hold = segments_after(PRELUDE, "CONTACT -X IN fixture FORCE 5 N UNTIL FORCE X < -1 N")
    expected = comparison(plan.Quantity.FORCE_ALONG, "<", -1.0, [0, 1, 0])
    check(approach, until=expected)
    check(hold, until=expected)


def test_clauses_in_any_order() -> None:
    a = segments_after(PRELUDE, "CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s")
    b = segments_after(PRELUDE, "CONTACT DOWN TIMEOUT 5 s SPEED 20 mm/s FORCE 8 N")
    for x, y in zip(a, b, strict=True):
        np.testing.assert_allclose(x.force_setpoint, y.force_setpoint)
        assert (x.speed_limit_mps, x.timeout_s) == (y.speed_limit_mps, y.timeout_s) == (0.02, 5.0)


# -------------------------------------------------------------------- OBSTACLE


def obstacle(line: str, prelude: str = "") -> plan.AddObstacle | plan.RemoveObstacle:
    steps, _ = steps_after(prelude, line)
    [step] = steps
    assert isinstance(step, plan.AddObstacle | plan.RemoveObstacle)
    return step


def test_cylinder_at_its_base_centre() -> None:
    step = obstacle("OBSTACLE post CYLINDER AT (0.4, -0.2, 0) RADIUS 40 mm HEIGHT 0.6 m")
    check_object(
        step,
        {
            "type": plan.AddObstacle,
            "name": "post",
            "shape": plan.ObstacleShape.CYLINDER,
            "position_world": [0.4, -0.2, 0.3],  # the plan holds the centre
            "rotation_world": I3,
            "radius_m": 0.04,
            "height_m": 0.6,
            "size_m": None,
            "velocity_world_mps": [0, 0, 0],
            "influence_m": None,
            "gain_scale": 1.0,
            "line": 1,
        },
        "post",
    )


def test_moving_sphere() -> None:
    step = obstacle("OBSTACLE ball SPHERE AT (0.4, 0.25, 0.5) RADIUS 60 mm MOVING (0, -50 mm/s, 0)")
    check_object(
        step,
        {
            "type": plan.AddObstacle,
            "shape": plan.ObstacleShape.SPHERE,
            "position_world": [0.4, 0.25, 0.5],
            "radius_m": 0.06,
            "height_m": None,
            "velocity_world_mps": [0, -0.05, 0],
        },
        "ball",
    )


def test_box_wall() -> None:
    step = obstacle("OBSTACLE wall BOX AT (0.6, 0, 0.3) SIZE (0.02, 0.6, 0.6)")
    check_object(
        step,
        {
            "type": plan.AddObstacle,
            "shape": plan.ObstacleShape.BOX,
            "position_world": [0.6, 0, 0.3],
            "size_m": [0.02, 0.6, 0.6],
            "radius_m": None,
        },
        "wall",
    )


def test_plane_with_normal_influence_and_gain() -> None:
    step = obstacle("OBSTACLE lid PLANE AT (0, 0, 1.2) NORMAL (0, 0, -2) INFLUENCE 150 mm GAIN 2")
    assert isinstance(step, plan.AddObstacle)
    np.testing.assert_allclose(step.rotation_world[:, 2], [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(step.rotation_world.T @ step.rotation_world, I3, atol=1e-12)
    assert (step.influence_m, step.gain_scale) == (pytest.approx(0.15), 2.0)


def test_obstacle_remove() -> None:
    step = obstacle("OBSTACLE REMOVE ball", prelude="OBSTACLE ball SPHERE AT (0, 0, 2) RADIUS 1 cm\n")
    check_object(step, {"type": plan.RemoveObstacle, "name": "ball"}, "remove")


# ---------------------------------------------------------- blocks, the example


def test_procedure_and_repeat_expand_with_spans_at_the_source() -> None:
    source = "PROC lift\n  MOVE BY (0, 0, 10 mm)\nEND\nREPEAT 3\n  lift\n  WAIT 1 s\nEND\nCALL lift\n"
    segments = compile_text(source).segments
    assert [s.kind for s in segments] == [plan.SegmentKind.MOVE, plan.SegmentKind.WAIT] * 3 + [
        plan.SegmentKind.MOVE
    ]
    assert [s.line for s in segments] == [2, 6, 2, 6, 2, 6, 2]
    assert [s.index for s in segments] == list(range(7))
    assert [s.statement_index for s in segments] == list(range(7))
    assert segments[2].context == "REPEAT pass 2 of 3 at line 4; PROC lift called at line 5"
    assert segments[3].context == "REPEAT pass 2 of 3 at line 4"
    assert segments[6].context == "PROC lift called at line 8"
    assert segments[0].statement == "MOVE BY (0, 0, 10 mm)"


PEG_IN_HOLE = """\
# peg into hole with a lateral error of 2 mm
FRAME above = hole + (2 mm, 0, 80 mm)
SPEED 0.25 m/s
MOVE TO above
CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s
INSERT DOWN DEPTH 25 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s
MOVE BY (0, 0, 100 mm)
"""


def test_the_contract_example_program() -> None:
    compiled = compile_text(PEG_IN_HOLE)
    assert compiled.warnings == ()
    move, approach, hold, insert, lift = compiled.segments
    assert len(compiled.steps) == 5
    check(
        move,
        kind=plan.SegmentKind.MOVE,
        line=4,
        target=absolute([0.602, 0.15, 0.34], DOWN_FACING),
        speed_limit_mps=0.25,
    )
    check(
        approach,
        kind=plan.SegmentKind.CONTACT_APPROACH,
        line=5,
        speed_limit_mps=0.02,
        timeout_s=5.0,
        target=relative([0, 0, -0.3]),
    )
    check(
        hold,
        kind=plan.SegmentKind.CONTACT_HOLD,
        line=5,
        motion_axes=[1, 1, 0, 1, 1, 1],
        force_setpoint=[0, 0, -8, 0, 0, 0],
    )
    check(
        insert,
        kind=plan.SegmentKind.INSERT,
        line=6,
        motion_axes=[0, 0, 0, 0, 0, 1],
        force_setpoint=[0, 0, -15, 0, 0, 0],
        timeout_s=10.0,
        completion={"type": plan.DepthReached, "direction_world": [0, 0, -1], "depth_m": 0.025},
    )
    check(
        lift,
        kind=plan.SegmentKind.MOVE,
        line=7,
        motion_axes=ALL_MOTION,
        target=relative([0, 0, 0.1]),
        speed_limit_mps=0.25,
    )
    assert [s.statement_index for s in compiled.segments] == [0, 1, 1, 2, 3]


# ------------------------------------------------------------------ coverage

CONTRACT = Path("/work/shared/reference/language.md")
COVERED = Path(__file__).read_text()


@pytest.mark.skipif(not CONTRACT.exists(), reason="the reference page is not on this machine")
def test_every_contract_example_is_covered() -> None:
    text = CONTRACT.read_text()
    statements = re.findall(r"`((?:MOVE|CONTACT|SLIDE|INSERT|COMPLY|OBSTACLE|LET|FRAME) [^`]*)`", text)
    placeholders = ("(...)", "...")
    missing = [s for s in statements if s not in COVERED and not any(p in s for p in placeholders)]
    assert not missing, missing
    assert len(statements) > 20
    assert set(FIXTURES) >= {"table", "hole", "slope"}


# ------------------------------------------------------ ORIENTATION and POSTURE


def test_orientation_free_frees_move_and_wait_but_not_contact() -> None:
    """The docs' example: MOVE and WAIT under ORIENTATION FREE leave the orientation to the null
    space, a CONTACT (and the WAIT holding its contact) keeps it, HELD ends it; POSTURE's angles
    in radians, ``home`` by name, NONE. Catches the flag on a force statement (its moments would
    lose their controller), HELD ignored, degrees kept as degrees, and a posture not carried."""
    program = (
        "ORIENTATION FREE\nPOSTURE (0 deg, 45 deg, -180 deg, 30 deg, -45 deg, 150 deg)\nWAIT 2 s\n"
        "MOVE BY (0, 50 mm, 0)\nPOSTURE home\nCONTACT DOWN FORCE 8 N\nWAIT 1 s\n"
        "ORIENTATION HELD\nPOSTURE NONE\nMOVE BY (0, 0, 50 mm)\n"
    )
    segments = compile_text(program).segments
    kinds = [s.kind for s in segments]
    assert kinds == [
        plan.SegmentKind.WAIT, plan.SegmentKind.MOVE, plan.SegmentKind.CONTACT_APPROACH,
        plan.SegmentKind.CONTACT_HOLD, plan.SegmentKind.WAIT, plan.SegmentKind.MOVE,
    ]  # fmt: skip
    assert [s.orientation_free for s in segments] == [True, True, False, False, False, False]
    wait, move, approach, _, held_wait, last = segments
    assert wait.posture is not None and wait.posture.name is None
    deg = math.pi / 180.0
    assert wait.posture.joints_rad == pytest.approx(
        (0.0, 45 * deg, -180 * deg, 30 * deg, -45 * deg, 150 * deg)
    )
    assert move.posture is wait.posture
    assert (
        approach.posture is not None
        and approach.posture.name == "home"
        and approach.posture.joints_rad is None
    )
    assert held_wait.posture is approach.posture
    assert last.posture is None
