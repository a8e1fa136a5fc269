"""The plan's helpers: stop-condition evaluation, quaternions, read-only arrays, bench."""

from __future__ import annotations

import math

import numpy as np
import pytest
from lang_support import compile_text

from cosmos import plan
from cosmos.bench.language import bench_compile
from cosmos.rotations import matrix_to_quaternion, rpy_to_matrix


def until(condition: str) -> plan.Condition:
    [segment] = compile_text(f"MOVE BY (0, 0, -0.1) UNTIL {condition}").segments
    assert segment.until is not None
    return segment.until


@pytest.mark.parametrize(
    ("condition", "force", "torque", "distance", "holds"),
    [
        ("FORCE > 5 N", [3, 4, 0.1], [0, 0, 0], 0.0, True),
        ("FORCE > 5 N", [3, 4, 0], [0, 0, 0], 0.0, False),
        ("FORCE Z < -3 N", [0, 0, -3.5], [0, 0, 0], 0.0, True),
        ("FORCE Z < -3 N", [0, 0, 3.5], [0, 0, 0], 0.0, False),
        ("FORCE DOWN > 3 N", [0, 0, -3.5], [0, 0, 0], 0.0, True),
        ("TORQUE RZ > 1 Nm", [0, 0, 0], [0, 0, 1.5], 0.0, True),
        ("DISTANCE >= 40 mm", [0, 0, 0], [0, 0, 0], 0.04, True),
        ("DISTANCE > 40 mm AND FORCE > 5 N", [0, 0, 9], [0, 0, 0], 0.05, True),
        ("DISTANCE > 40 mm AND FORCE > 5 N", [0, 0, 9], [0, 0, 0], 0.03, False),
        ("DISTANCE > 40 mm OR FORCE > 5 N", [0, 0, 9], [0, 0, 0], 0.03, True),
    ],
)
def test_condition_holds(
    condition: str, force: list[float], torque: list[float], distance: float, holds: bool
) -> None:
    assert plan.condition_holds(until(condition), np.array(force), np.array(torque), distance) is holds


def test_quaternion_of_known_rotations() -> None:
    # Half-turn about x: (w, x, y, z) = (0, 1, 0, 0); quarter turn about z: cos/sin of 45 deg.
    np.testing.assert_allclose(matrix_to_quaternion(rpy_to_matrix(math.pi, 0, 0)), [0, 1, 0, 0], atol=1e-12)
    half = math.sqrt(0.5)
    np.testing.assert_allclose(
        matrix_to_quaternion(rpy_to_matrix(0, 0, math.pi / 2)), [half, 0, 0, half], atol=1e-12
    )


def test_quaternion_rotates_like_its_matrix() -> None:
    rng = np.random.default_rng(7)
    for _ in range(20):
        rotation = rpy_to_matrix(*rng.uniform(-math.pi, math.pi, 3))
        w, x, y, z = matrix_to_quaternion(rotation)
        v = rng.normal(size=3)
        # q v q* with the Hamilton product, computed without the matrix
        u = np.array([x, y, z])
        rotated = v + 2 * w * np.cross(u, v) + 2 * np.cross(u, np.cross(u, v))
        np.testing.assert_allclose(rotated, rotation @ v, atol=1e-12)


def test_plan_arrays_are_read_only() -> None:
    [segment] = compile_text("MOVE BY (0, 0, 0.1)").segments
    for array in (segment.frame_rotation, segment.motion_axes, segment.force_setpoint):
        with pytest.raises(ValueError):
            array[0] = 1
    assert isinstance(segment.target, plan.RelativeTarget)
    with pytest.raises(ValueError):
        segment.target.offset_world[0] = 1.0


def test_bench_compile_returns_seconds() -> None:
    seconds = bench_compile(lines=200)
    assert 0 < seconds < 60
