"""Goals, force setpoints and orientation angles of the plot against independent computations."""

import numpy as np
import pytest

from cosmos.replay.setpoints import force_setpoint_world, goal_steps, rpy_degrees
from cosmos.rotations import matrix_to_quaternion, rpy_to_matrix
from cosmos.runlog.reader import SegmentRecord


def segment(t: float, axes: tuple[int, ...], frame_wxyz=(1.0, 0.0, 0.0, 0.0), force=(0.0,) * 6, goal=None):
    zeros = (0.0,) * 6
    return SegmentRecord(t, 0, 1, "S", "move", frame_wxyz, axes, force, zeros, zeros, goal, None, None)


def test_force_setpoint_is_rotated_to_world_and_only_on_force_axes() -> None:
    """Catches the task-frame setpoint drawn unrotated, with the quaternion read as x y z w, or
    including motion-controlled axes (which apply no force)."""
    half = np.sqrt(0.5)
    about_z = (half, 0.0, 0.0, half)  # task x = world y, task y = world -x
    s = segment(0.0, (0, 1, 0, 1, 1, 1), about_z, force=(10.0, 7.0, -5.0, 0, 0, 0))
    assert force_setpoint_world(s) == pytest.approx([0.0, 10.0, -5.0])
    assert force_setpoint_world(segment(0.0, (1,) * 6, force=(3.0, 0, 0, 0, 0, 0))) is None


def test_goal_steps_hold_from_a_segment_to_the_next() -> None:
    """Catches goals drawn past the next segment's start, or segments without goals drawn."""
    steps = goal_steps(
        [
            segment(1.0, (1,) * 6, goal=(0.1, 0.2, 0.3)),
            segment(0.0, (1,) * 6),
            segment(2.5, (1,) * 6, goal=(1, 2, 3, 1, 0, 0, 0)),
        ],
        end=4.0,
    )
    assert [(s.start, s.stop, s.value.tolist()) for s in steps] == [
        (1.0, 2.5, [0.1, 0.2, 0.3]),
        (2.5, 4.0, [1.0, 2.0, 3.0]),
    ]


def test_rpy_degrees_inverts_the_languages_rpy() -> None:
    """Catches angles in another convention than the language's RPY (fixed x, then y, then z)."""
    rng = np.random.default_rng(3)
    angles = rng.uniform([-170, -80, -170], [170, 80, 170], size=(20, 3))
    quats = np.array([matrix_to_quaternion(rpy_to_matrix(*np.radians(a))) for a in angles])
    got = np.array([rpy_degrees(q[None, :])[0] for q in quats])
    np.testing.assert_allclose(got, angles, atol=1e-9)
    assert np.isnan(rpy_degrees(np.array([[np.nan, 0, 0, 1.0]]))).all()
