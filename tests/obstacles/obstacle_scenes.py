"""Runs a goal motion from home among obstacles and measures it with the simulator (not a test module).

Everything judged here is read from MuJoCo, independently of the controller:
the tool point is the scene's ``tool`` site, clearances are ``mj_geomDistance``
between the arm's geoms and the obstacles' geoms, contacts are MuJoCo's.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import mujoco
import numpy as np

from cosmos.obstacles import (
    FieldParameters,
    LocalMinimum,
    LocalMinimumDetector,
    Obstacle,
    ObstacleField,
    ObstacleScene,
    collisions,
    obstacle_scene_xml,
)
from cosmos.obstacles.capsules import ARM_BODIES
from cosmos.plant import Plant
from cosmos.robot_model import RobotModel, build_robot_model
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint
from cosmos.workcell import TOOL_SITE

CLEARANCE_EVERY_TICKS = 10


@functools.cache
def robot() -> RobotModel:
    return build_robot_model()


@dataclass(frozen=True)
class Scene:
    """A goal motion from home (tool orientation kept) among obstacles."""

    name: str
    obstacles: tuple[Obstacle, ...]
    goal: tuple[float, float, float]
    duration_s: float
    max_speed: float = 0.25


@dataclass
class Outcome:
    goal_error_m: float = np.inf
    min_clearance_m: float = np.inf
    contacts: list[tuple[str, str]] = field(default_factory=list)
    local_minimum: LocalMinimum | None = None
    duration_s: float = 0.0


def _arm_geoms(model: mujoco.MjModel) -> list[int]:
    return [g for g in range(model.ngeom) if model.body(int(model.geom_bodyid[g])).name in ARM_BODIES]


def run(
    scene: Scene,
    avoid: bool = True,
    stop_on_contact: bool = False,
    stop_at_goal_m: float = 0.0,
    detect: bool = False,
    parameters: FieldParameters | None = None,
) -> Outcome:
    """Drive the arm from home to ``scene.goal`` with the obstacle field on (``avoid``) or off."""
    plant = Plant(obstacle_scene_xml())
    runtime = Runtime(plant, robot())
    world = ObstacleScene(plant)
    potential = ObstacleField(robot()) if parameters is None else ObstacleField(robot(), parameters)
    potential.enabled = avoid
    for obstacle in scene.obstacles:
        world.add(obstacle)
        potential.add(obstacle)
    runtime.fields.append(potential)
    ev = runtime.evaluation
    goal = np.array(scene.goal)
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.GOAL,
            position=goal,
            rotation_to_world=ev.rotation_tool_to_world,
            start_s=0.0,
            max_speed=scene.max_speed,
        )
    )
    model, data = plant.model, plant.data
    tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
    arm = _arm_geoms(model)
    slots = world.body_names()  # slot geom -> obstacle
    obstacle_geoms = [int(model.geom(geom).id) for geom in slots]
    detector = LocalMinimumDetector() if detect else None
    outcome = Outcome()
    fromto = np.zeros(6)
    ticks = int(round(scene.duration_s * runtime.rates.servo_hz))
    for tick in range(ticks):
        world.update(plant.time_s)
        runtime.tick()
        error = float(np.linalg.norm(data.site_xpos[tool] - goal))
        for hit in collisions(plant, slots):
            if hit.is_obstacle and (hit.arm_body, hit.other) not in outcome.contacts:
                outcome.contacts.append((hit.arm_body, hit.other))
        if tick % CLEARANCE_EVERY_TICKS == 0:
            for g1 in arm:
                for g2 in obstacle_geoms:
                    d = mujoco.mj_geomDistance(model, data, g1, g2, 1.0, fromto)
                    outcome.min_clearance_m = min(outcome.min_clearance_m, d)
        if detector is not None:
            found = detector.update(plant.time_s, error, potential.influences)
            if found is not None:
                outcome.local_minimum = found
                break
        if stop_on_contact and outcome.contacts:
            break
        if stop_at_goal_m > 0.0 and error < stop_at_goal_m and np.linalg.norm(runtime.qd) < 0.01:
            break
    outcome.goal_error_m = float(np.linalg.norm(data.site_xpos[tool] - goal))
    outcome.duration_s = plant.time_s
    return outcome
