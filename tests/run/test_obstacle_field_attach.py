"""The obstacle field is in the runtime only while an obstacle is in the scene (issue 20, item 4)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cosmos.execution.session import Session
from cosmos.lang import compile_program
from cosmos.runtime.rates import Rates
from cosmos.workcell import fixture_frames

PROGRAM = """\
OBSTACLE ball SPHERE AT (0.45, 0.25, 0.45) RADIUS 50 mm
WAIT 50 ms
OBSTACLE REMOVE ball
WAIT 50 ms
"""


def test_the_field_leaves_with_the_last_obstacle(tmp_path: Path) -> None:
    """Catches a field left in the parameter level with no obstacle (its evaluations cost every tick
    of every run), a field torque left acting after the last obstacle is removed, and the contact
    gate left on the physics steps without obstacles or not put on them with the first."""
    plan = compile_program(PROGRAM, "field.cos", fixture_frames())
    with Session("field.cos", PROGRAM, tmp_path / "run.mcap", Rates()) as session:
        runtime, world = session.runtime, session.obstacles
        assert runtime.fields == []
        seen: list[bool] = []
        run_statement = session.executor.run_statement

        def watch(segments):  # type: ignore[no-untyped-def]
            seen.append(world.field in runtime.fields and runtime.contact_gate is world.gate)
            return run_statement(segments)

        session.executor.run_statement = watch  # type: ignore[method-assign]
        session.executor.run(plan)
        assert seen == [True, False]  # the first WAIT among the ball, the second without
        assert runtime.fields == []
        assert runtime.contact_gate is None
        np.testing.assert_array_equal(runtime.servo.field_torque, np.zeros(6))
