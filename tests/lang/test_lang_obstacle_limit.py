"""The checker knows how many obstacles the workcell holds (issue 20, item 4)."""

from __future__ import annotations

import pytest
from lang_support import FIXTURES

from cosmos.errors import ProgramError
from cosmos.lang import compile_program
from cosmos.lang.check.limits import MAX_OBSTACLES


def _obstacles(count: int, first: int = 0) -> str:
    return "".join(
        f"OBSTACLE b{i} SPHERE AT ({0.1 + 0.001 * i:.3f}, -0.6, 0.2) RADIUS 5 mm\n"
        for i in range(first, first + count)
    )


def test_the_limit_is_the_workcells_slot_count() -> None:
    """Catches a checker limit that drifts from the scene: the workcell as MuJoCo compiles it has
    exactly this many obstacle slot geoms, so a program check passes is one the run can hold."""
    import mujoco

    from cosmos.obstacles.scene import SLOT_PREFIX, obstacle_scene_xml

    model = mujoco.MjModel.from_xml_path(str(obstacle_scene_xml()))
    slots = [model.geom(i).name for i in range(model.ngeom) if model.geom(i).name.startswith(SLOT_PREFIX)]
    assert len(slots) == MAX_OBSTACLES >= 64


def test_a_scene_may_hold_the_limit_and_exchange_obstacles() -> None:
    """Catches a limit that counts OBSTACLE statements rather than obstacles in the scene at once:
    64 present, one removed, another added, is a valid program."""
    source = _obstacles(MAX_OBSTACLES) + "OBSTACLE REMOVE b3\n" + _obstacles(1, MAX_OBSTACLES)
    plan = compile_program(source, "full.cos", FIXTURES)
    assert len(plan.steps) == MAX_OBSTACLES + 2


def test_one_more_is_a_located_error() -> None:
    """Catches a 65th obstacle that passes check and fails at run time (issue 20's finding)."""
    with pytest.raises(ProgramError) as caught:
        compile_program(_obstacles(MAX_OBSTACLES + 1), "over.cos", FIXTURES)
    assert caught.value.span is not None and caught.value.span.line == MAX_OBSTACLES + 1
    assert f"at most {MAX_OBSTACLES} obstacles" in caught.value.message
