"""What the REPL shows and keeps, without the arm: angles, force axes, transcript lines, state repair."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.errors import ProgramError
from cosmos.lang import Compiler
from cosmos.plan import AddObstacle, Segment
from cosmos.repl.statements import state_after_failure, statement_groups
from cosmos.repl.status import force_directions, format_pose, matrix_to_rpy
from cosmos.repl.transcript import Transcript
from cosmos.rotations import rpy_to_matrix
from cosmos.workcell import fixture_frames


def test_rpy_inverts_the_languages_rpy() -> None:
    rng = np.random.default_rng(7)
    for roll, pitch, yaw in rng.uniform([-np.pi, -1.5, -np.pi], [np.pi, 1.5, np.pi], size=(200, 3)):
        recovered = matrix_to_rpy(rpy_to_matrix(roll, pitch, yaw))
        np.testing.assert_allclose(rpy_to_matrix(*recovered), rpy_to_matrix(roll, pitch, yaw), atol=1e-12)
        np.testing.assert_allclose(recovered, [roll, pitch, yaw], atol=1e-9)


def test_rpy_at_gimbal_lock_still_gives_the_rotation() -> None:
    rotation = rpy_to_matrix(0.3, np.pi / 2, -0.4)
    np.testing.assert_allclose(rpy_to_matrix(*matrix_to_rpy(rotation)), rotation, atol=1e-9)


def test_pose_text_reads_like_the_language() -> None:
    pose = format_pose(np.array([0.6, -0.15, 0.2]), rpy_to_matrix(np.pi, 0.0, 0.0))
    assert pose == "(600, -150, 200) mm RPY (180, 0, 0) deg"


def _omega_bar(force_axes_task: list[int], rotation_task_to_world: np.ndarray) -> np.ndarray:
    """Omega_bar = blkdiag(R S R^T, R S' R^T) for the task axes listed as force-controlled."""
    s = np.zeros(6)
    s[force_axes_task] = 1.0
    r = rotation_task_to_world
    out = np.zeros((6, 6))
    out[:3, :3] = r @ np.diag(s[:3]) @ r.T
    out[3:, 3:] = r @ np.diag(s[3:]) @ r.T
    return out


def test_force_axes_named_in_world_axes() -> None:
    assert force_directions(None) == []
    assert force_directions(np.zeros((6, 6))) == []
    assert force_directions(_omega_bar([2], np.eye(3))) == ["Z"]
    assert force_directions(_omega_bar([0, 1, 3, 4], np.eye(3))) == ["X", "Y", "RX", "RY"]
    # A tool-down task frame (x kept, y and z flipped): its z is still the world's Z axis.
    assert force_directions(_omega_bar([2], rpy_to_matrix(np.pi, 0, 0))) == ["Z"]


def test_force_axis_of_a_tilted_frame_is_given_as_a_direction() -> None:
    tilted = fixture_frames()["slope"].rotation
    (direction,) = force_directions(_omega_bar([2], tilted))
    z = tilted[:, 2] * np.sign(tilted[np.argmax(np.abs(tilted[:, 2])), 2])
    assert direction == "(" + ", ".join(f"{v:.2f}".rstrip("0").rstrip(".") for v in z) + ")"


def test_transcript_lines_are_the_compiled_lines() -> None:
    compiler = Compiler(fixture_frames())
    transcript = Transcript()
    state = compiler.initial_state()
    for text in ["SPEED 0.2 m/s", "PROC down\n  MOVE BY (0, 0, -1 mm)\nEND", "WAIT 1 s; WAIT 2 s"]:
        result = compiler.compile_text(transcript.placed(text), state)
        state = result.state
        transcript.add_statements(text)
    transcript.add_command(":state")
    transcript.add_rejected("MOVE BY (0, 0, 1 mx)\n")
    with pytest.raises(ProgramError) as caught:
        compiler.compile_text(transcript.placed("MOVE BY (1 mx)"), state)
    assert caught.value.span is not None and caught.value.span.line == 8
    result = compiler.compile_text(transcript.placed("down"), state)
    lines = transcript.text().splitlines()
    assert lines[5:] == ["# :state", "# ! MOVE BY (0, 0, 1 mx)"]
    (segment,) = result.steps
    assert isinstance(segment, Segment)
    assert lines[segment.line - 1].strip() == segment.statement == "MOVE BY (0, 0, -1 mm)"
    compiler.compile_program(transcript.text(), "<transcript>")  # the transcript is a program


def test_failure_leaves_no_contact_and_only_obstacles_that_were_added() -> None:
    compiler = Compiler(fixture_frames())
    before = compiler.compile_text("CONTACT DOWN FORCE 5 N", compiler.initial_state()).state
    text = (
        "OBSTACLE a SPHERE AT (0.4, 0.3, 0.5) RADIUS 50 mm\n"
        "OBSTACLE b SPHERE AT (0.4, -0.3, 0.5) RADIUS 50 mm\n"
        "SLIDE +X BY 10 mm"
    )
    result = compiler.compile_text(text, before)
    assert result.state.contact is not None and set(result.state.obstacles) == {"a", "b"}
    groups = list(statement_groups(result.steps))
    assert [type(g[0]) for g in groups] == [AddObstacle, AddObstacle, Segment]
    failed = groups[1][0].span
    repaired = state_after_failure(before, result.state, list(groups[0]), failed)
    assert repaired.contact is None
    assert repaired.contact_released_by == failed
    assert set(repaired.obstacles) == {"a"}
