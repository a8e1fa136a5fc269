"""The compiler's value-keyed caches give what computing afresh gives.

The compiler remembers rotations by their angles, signed frame axes by the
rotation's bytes, and axis setups by the COMPLY numbers (not the COMPLY
statement): these tests check the remembered values against ones written out
here, and that a changed input is not served a stale value.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from lang_support import compile_text

from cosmos import plan
from cosmos.lang.rotations import rpy_to_matrix, signed_column

ANGLES = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)


def _rpy_by_hand(roll: float, pitch: float, yaw: float) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = (
        math.cos(roll),
        math.sin(roll),
        math.cos(pitch),
        math.sin(pitch),
        math.cos(yaw),
        math.sin(yaw),
    )
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


@given(ANGLES, ANGLES, ANGLES)
def test_remembered_rotation_is_the_rotation_of_its_angles(roll: float, pitch: float, yaw: float) -> None:
    first = rpy_to_matrix(roll, pitch, yaw)
    again = rpy_to_matrix(roll, pitch, yaw)
    assert np.allclose(first, _rpy_by_hand(roll, pitch, yaw), atol=1e-12)
    assert np.array_equal(first, again)
    assert not first.flags.writeable and not again.flags.writeable


@given(ANGLES, ANGLES, ANGLES, st.integers(0, 2), st.sampled_from([1, -1]))
def test_signed_column_is_the_frame_axis(roll: float, pitch: float, yaw: float, axis: int, sign: int) -> None:
    rotation = _rpy_by_hand(roll, pitch, yaw)
    array, values = signed_column(rotation, axis, sign)
    expected = [sign * rotation[row, axis] + 0.0 for row in range(3)]
    assert array.tolist() == expected
    assert list(values) == expected
    assert not array.flags.writeable


def test_signed_column_has_no_negative_zero() -> None:
    array, values = signed_column(np.eye(3), 0, -1)
    assert [math.copysign(1.0, v) for v in values] == [-1.0, 1.0, 1.0]
    assert [math.copysign(1.0, v) for v in array] == [-1.0, 1.0, 1.0]


def _segments(source: str) -> list[plan.Segment]:
    return [step for step in compile_text(source).steps if isinstance(step, plan.Segment)]


def test_axis_setup_follows_the_comply_numbers_not_a_stale_one() -> None:
    segments = _segments(
        "COMPLY X STIFFNESS 100 N/m\nMOVE BY (0, 0, 10 mm)\n"
        "COMPLY X STIFFNESS 200 N/m DAMPING 5 N s/m\nMOVE BY (0, 0, 10 mm)\n"
        "COMPLY X STIFFNESS 100 N/m\nMOVE BY (0, 0, 10 mm)\n"
        "COMPLY X STIFFNESS 0 N/m\nWAIT 1 s\n"
    )
    assert [s.stiffness[0] for s in segments] == [100.0, 200.0, 100.0, 0.0]
    assert [s.damping[0] for s in segments] == [None, 5.0, None, None]
    assert segments[-1].motion_axes.tolist() == [False, True, True, True, True, True]
    assert segments[0].motion_axes.tolist() == [True] * 6


def test_contact_axis_is_read_in_each_statements_frame() -> None:
    # The same held contact, read in the world and in a frame turned 90 deg about z.
    segments = _segments("CONTACT DOWN FORCE 5 N\nSLIDE +X BY 10 mm IN world\nSLIDE +X BY 10 mm IN fixture\n")
    hold, world_slide, fixture_slide = segments[1:]
    assert hold.force_setpoint.tolist() == [0, 0, -5, 0, 0, 0]
    assert world_slide.force_setpoint.tolist() == [0, 0, -5, 0, 0, 0]
    assert fixture_slide.force_setpoint.tolist() == [0, 0, -5, 0, 0, 0]
    assert np.allclose(world_slide.target.offset_world, [0.01, 0, 0])  # type: ignore[union-attr]
    assert np.allclose(fixture_slide.target.offset_world, [0, 0.01, 0])  # type: ignore[union-attr]
