"""The checker's declared home tool pose, per arm and TOOL, against the scenes MuJoCo compiles."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.api import check
from cosmos.capabilities import HOME_TOOLS
from cosmos.errors import ProgramError
from cosmos.robots import ROBOTS
from cosmos.runtime import foresight_cache


@pytest.mark.parametrize(("robot", "tool"), sorted(HOME_TOOLS))
def test_each_declared_home_is_its_scenes(robot: str, tool: str) -> None:
    """Each (arm, tool) home pose the checker judges timed moves from is where MuJoCo puts that
    tool's point at the scene's home keyframe. Catches the PUMA peg's home used for the gripper
    (12.5 mm off) and for the Panda's hand (45.4 mm off), as the timed-move check did."""
    scene = foresight_cache.from_scene(ROBOTS[robot], tool)
    declared = HOME_TOOLS[(robot, tool)]
    assert np.allclose(declared.position, scene.home_tool_position, atol=1e-9)
    assert np.allclose(declared.rotation, scene.home_tool_rotation, atol=1e-9)


def test_a_timed_move_with_the_panda_hand_is_judged_from_the_hands_home() -> None:
    """A 1 ms MOVE TO the peg's home point with the Panda's hand on is 45 mm of travel, refused
    with its shortest duration. Catches the check measuring from the peg's home (0 mm: accepted)."""
    peg_home = ", ".join(f"{value * 1e3:.4f} mm" for value in HOME_TOOLS[("panda", "peg")].position)
    with pytest.raises(ProgramError) as error:
        check(f"ROBOT panda\nTOOL GRIPPER\nMOVE TO ({peg_home}) IN 1 ms\n")
    assert "cannot move 45 mm in 0.001 s" in error.value.message
    check(f"ROBOT panda\nMOVE TO ({peg_home}) IN 1 ms\n")  # the peg is there already
