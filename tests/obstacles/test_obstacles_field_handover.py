"""The runtime hands the obstacle field to the servo in one call, skipped only when nothing changed."""

from __future__ import annotations

import numpy as np

from cosmos.obstacles import FieldParameters, ObstacleField, ObstacleScene, obstacle_scene_xml
from cosmos.obstacles.obstacle import sphere
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint


def test_the_servo_holds_the_fields_torque_after_every_evaluation() -> None:
    """A ball flies past the still tool (0.4 m/s, 60 mm beside its path at the closest), so the field
    goes from nothing to acting and back to nothing. After every parameter evaluation the servo must
    hold what a second field of the same ball gives at the same state and time, split the same way
    (tool's link, the others, the nearest link). Catches the runtime's one-call path keeping an old
    field in the servo after the field changed (a hand-over skipped while the field pushes, or when it
    stops pushing: the servo would push the arm away from a ball that has gone), and a split or a
    nearest link that differs from the field's own."""
    robot = build_robot_model()
    plant = Plant(obstacle_scene_xml())
    runtime = Runtime(plant, robot)
    parameters = FieldParameters(period_s=0.0)
    field, reference = ObstacleField(robot, parameters), ObstacleField(robot, parameters)
    tool = runtime.evaluation.position.copy()
    ball = sphere("ball", (tool[0] + 0.09, -0.60, tool[2]), 0.03, velocity_mps=(0.0, 0.4, 0.0))
    world = ObstacleScene(plant)
    world.add(ball)
    field.add(ball)
    reference.add(ball)
    runtime.fields.append(field)
    runtime.set_setpoint(
        ServoSetpoint(
            MotionMode.GOAL, tool, runtime.evaluation.rotation_tool_to_world, start_s=0.0, max_speed=0.2
        )
    )
    asked: list[tuple[np.ndarray, np.ndarray, float]] = []
    torque_of = field.torque

    def watched(q: np.ndarray, qd: np.ndarray, t_s: float) -> np.ndarray:
        asked.append((q.copy(), qd.copy(), t_s))
        return torque_of(q, qd, t_s)

    field.torque = watched  # type: ignore[method-assign]
    phases = []
    for _ in range(2200):
        world.update(plant.time_s)
        runtime.tick()
        if not asked:
            continue
        q, qd, t_s = asked.pop()
        torque = reference.torque(q, qd, t_s)
        held = runtime.servo.link_field
        np.testing.assert_array_equal(held.links, reference.link_torque)
        np.testing.assert_array_equal(held.tool, torque - reference.link_torque)
        assert (held.clearance_m, held.link, held.obstacle) == reference.nearest_link
        pushing = bool(np.any(torque))
        if not phases or phases[-1] != pushing:
            phases.append(pushing)
    assert phases == [False, True, False]  # it came, acted and went
