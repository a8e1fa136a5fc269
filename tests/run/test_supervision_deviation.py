"""The tool's distance from its path, in one compiled call for the live tool point (issue 20).

The field on the tool's watch asks the supervisor every tick of an episode how far the tool is
off its commanded line (:meth:`cosmos.execution.supervision.Supervisor.path_deviation_m`); for the
live tool point the ticks look at, a compiled call on the supervisor's listed arrays answers
(:func:`cosmos.execution.supervision_kernel.path_deviation_listed`). Compared here, to the last
bit, with :func:`cosmos.execution.expected.off_line` in Python on the same line and axes.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.execution.expected import off_line
from cosmos.execution.supervision import Supervisor
from cosmos.lang import compile_program
from cosmos.obstacles import obstacle_scene_xml
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.workcell import fixture_frames

ROBOT = build_robot_model()


@pytest.mark.parametrize(
    "program",
    ["MOVE BY (100 mm, 0, 0)\n", "CONTACT DOWN FORCE 10 N\nSLIDE +X BY 50 mm SPEED 10 mm/s\n", "WAIT 1 s\n"],
)
def test_the_compiled_deviation_is_off_line_on_the_same_line_and_axes(program: str) -> None:
    """Random lines (some too short to have a direction, some passed or not reached) and tool points,
    on a segment's free translation axes (the three of a MOVE or a WAIT, the two of a SLIDE).
    Catches the listed view reading another array than the tool point, the line or the axes, or the
    line not brought up to date by a VIA leg."""
    plant = Plant(obstacle_scene_xml())
    supervisor = Supervisor(plant, np.minimum(-ROBOT.tau_lower_nm, ROBOT.tau_upper_nm), 0.001)
    segment = compile_program(program, "s.cos", fixture_frames()).segments[-1]  # the last statement's
    position, wrench, torque = np.zeros(3), np.zeros(6), np.zeros(6)
    supervisor.start(segment, position, position)
    supervisor.check(0.0, wrench, torque, position)  # lists the live views
    rng = np.random.default_rng(3)
    axes = [
        tuple(segment.frame_rotation[:, i].tolist())
        for i in range(3)
        if segment.motion_axes[i] and segment.stiffness[i] is None
    ]
    for _ in range(300):
        start = rng.normal(0.0, 0.3, 3)
        end = start + rng.normal(0.0, 0.2, 3) * (rng.uniform() > 0.1)  # a tenth: a point, not a line
        supervisor.leg(start, end)
        position[:] = start + rng.uniform(-0.5, 1.5) * (end - start) + rng.normal(0.0, 0.05, 3)
        line = end - start
        expected = off_line(
            position.tolist(), tuple(start.tolist()), tuple(line.tolist()), float(line @ line), axes
        )
        assert supervisor.path_deviation_m(position) == expected
        assert supervisor.path_deviation_m(position.copy()) == expected  # not listed: in Python
