"""The cost of obstacle avoidance in the servo loop: ticks among 0, 10 and 50 obstacles against a bare tick.

Runtimes built as the executor builds them (the workcell with its obstacle
slots, the obstacle field and the contact gate installed while there are
obstacles) make the same goal motions (from home
400 mm sideways and back, speed limit 0.25 m/s): among no obstacle, among ten
(spheres, boxes, posts, a plane, one of them moving; about four within the
influence distance at any time), and among fifty (the ten and forty spheres
around the arm's reach). The *bare* runtime is the controller alone: the
workcell without slots, no field. A tick includes everything the executor does
per servo period for obstacles: moving the obstacles, sensing, the parameter
level (with the field, at its rate), the servo and the physics. The runs
alternate in short chunks so that the load of a shared machine affects all
alike, and the time measured is this process's CPU time (what other processes
on a shared machine take is not counted); the median chunk is reported.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

import numpy as np

from cosmos.obstacles.field import ObstacleField
from cosmos.obstacles.gate import ContactGate
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.obstacles.scene import DEFAULT_SLOTS, ObstacleScene, obstacle_scene_xml
from cosmos.plan import ObstacleShape
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

CHUNK_TICKS = 200
PHYSICS_TICKS = 1000  # ticks per configuration over which MuJoCo's steps are timed, after the ratios
LEG_S = 2.0  # each goal is held this long before the next


def bench_scene() -> tuple[Obstacle, ...]:
    """Ten obstacles about the sideways move; the arm gets past them."""
    floor = Obstacle(
        "floor",
        ObstacleShape.PLANE,
        np.array((0.0, 0.0, 0.30)),
        np.eye(3),
        np.array((np.inf, np.inf, 0.0)),
        np.zeros(3),
    )
    return (
        sphere("ball", (0.61, 0.05, 0.52), 0.05),
        sphere("rock", (0.42, 0.0, 0.73), 0.05),
        sphere("moving", (0.45, 0.10, 0.53), 0.05, velocity_mps=(0.05, 0.0, 0.0)),
        box("wall", (0.79, -0.05, 0.62), (0.02, 0.6, 0.5)),
        box("crate", (0.62, -0.45, 0.30), (0.12, 0.12, 0.12)),
        box("shelf", (0.20, 0.60, 0.50), (0.30, 0.05, 0.40)),
        cylinder("post", (0.30, -0.50, 0.50), 0.04, 1.0),
        cylinder("pillar", (-0.40, 0.30, 0.60), 0.06, 1.2),
        cylinder("lamp", (0.60, -0.15, 1.45), 0.05, 0.3),
        floor,
    )


def crowded_scene(count: int = 50) -> tuple[Obstacle, ...]:
    """:func:`bench_scene` and ``count - 10`` spheres on shells around the arm's reach (5 cm radius).

    They stand behind and beside the arm (x < 0.3 m or |y| > 0.75 m), so the goal
    motions stay free, and the links pass within the influence distance of a few.
    """
    extra = []
    for index in range(max(0, count - 10)):
        angle = np.pi * (0.55 + 0.9 * (index % 10) / 9.0)  # behind the base, 99 to 261 deg
        shell = 0.75 + 0.15 * ((index // 10) % 2)
        height = 0.35 + 0.3 * (index // 20) + 0.1 * (index % 3)
        extra.append(sphere(f"extra{index}", (shell * np.cos(angle), shell * np.sin(angle), height), 0.05))
    return bench_scene()[: min(count, 10)] + tuple(extra)


def _runner(
    obstacles: tuple[Obstacle, ...], bare: bool = False
) -> tuple[Runtime, Callable[[int], None], ObstacleField | None]:
    """A runtime as the executor builds it (workcell with obstacle slots, field installed), or bare."""
    robot = build_robot_model()
    plant = Plant() if bare else Plant(obstacle_scene_xml(max(DEFAULT_SLOTS, len(obstacles))))
    runtime = Runtime(plant, robot)
    world = None if bare else ObstacleScene(plant)
    field = None if bare else ObstacleField(robot)
    if world is not None and field is not None:
        for obstacle in obstacles:
            world.add(obstacle)
            field.add(obstacle)
        if obstacles:  # as the executor does: the field and the gate act while an obstacle is in the scene
            runtime.fields.append(field)
            runtime.contact_gate = ContactGate(plant, world.version)
    home = runtime.evaluation.position.copy()
    rotation = runtime.evaluation.rotation_tool_to_world.copy()
    goals = (home + np.array((0.0, 0.4, 0.0)), home)
    leg = [-1]

    def ticks(count: int) -> None:
        for _ in range(count):
            now = runtime.time_s
            current = int(now // LEG_S) % 2
            if current != leg[0]:
                leg[0] = current
                runtime.set_setpoint(
                    ServoSetpoint(MotionMode.GOAL, goals[current], rotation, start_s=now, max_speed=0.25)
                )
            if world is not None:
                world.update(now)
            runtime.tick()

    return runtime, ticks, field


class _TimedPhysics:
    """Adds up the CPU time of a plant's physics steps (``Plant.advance``, MuJoCo's ``mj_step``)."""

    def __init__(self, plant: Plant) -> None:
        self.ns = 0
        advance = plant.advance

        def timed() -> float:
            start = time.process_time_ns()
            t_s = advance()
            self.ns += time.process_time_ns() - start
            return t_s

        plant.advance = timed  # type: ignore[method-assign]


class _Timed:
    """Adds up the CPU time of a potential field's evaluations (its ``torque``, wrapped in place)."""

    def __init__(self, field: ObstacleField) -> None:
        self.ns = 0
        torque = field.torque

        def timed(q: np.ndarray, qd: np.ndarray, t_s: float) -> np.ndarray:
            start = time.process_time_ns()
            result = torque(q, qd, t_s)
            self.ns += time.process_time_ns() - start
            return result

        field.torque = timed  # type: ignore[method-assign]


def bench_obstacles(ticks: int = 4000, counts: tuple[int, ...] = (0, 10, 50)) -> dict[str, float]:
    """Measure the servo tick bare and among ``counts`` obstacles (CPU time; still noisy on a shared machine).

    Args:
        ticks: Servo ticks per configuration (simulated seconds x 1000).
        counts: Numbers of obstacles, each at most 10 or a :func:`crowded_scene`.

    Returns:
        ``tick_us_bare`` and ``tick_us_<n>`` per count (median per-tick CPU time of the
        chunks, in microseconds), ``ratio_<n>`` (to the bare tick), and over
        :data:`PHYSICS_TICKS` more ticks, timed apart: ``field_us_per_tick_<n>`` (CPU time of
        the field per servo tick, its evaluations spread over the ticks),
        ``physics_us_per_tick_bare`` and ``physics_us_per_tick_<n>`` (mean CPU time of
        MuJoCo's steps per tick): what the obstacles cost where,
        ``in_influence_<n>`` (mean obstacles within the influence distance) and ``ticks``.
    """
    runners: dict[str, Callable[[int], None]] = {}
    timers: dict[str, _Timed] = {}
    physics: dict[str, _TimedPhysics] = {}
    fields: dict[str, ObstacleField] = {}
    plants: dict[str, Plant] = {}
    runtime, runners["bare"], _ = _runner((), bare=True)
    plants["bare"] = runtime.plant
    for count in counts:
        runtime, runners[str(count)], field = _runner(crowded_scene(count) if count else ())
        assert field is not None
        fields[str(count)] = field
        plants[str(count)] = runtime.plant
    for run in runners.values():  # warm up (caches, first evaluations)
        run(CHUNK_TICKS)
    chunks: dict[str, list[float]] = {key: [] for key in runners}
    influenced: dict[str, list[int]] = {key: [] for key in fields}
    clock = time.process_time_ns  # CPU time of this process: other processes' load does not count
    rounds = max(1, ticks // CHUNK_TICKS)
    for _ in range(rounds):
        for key, run in runners.items():
            start = clock()
            run(CHUNK_TICKS)
            chunks[key].append((clock() - start) / CHUNK_TICKS)
            if key in fields:
                influenced[key].append(len(fields[key].influences))
    # Then MuJoCo's and the field's shares, in a pass of their own: their clocks cost a tick as much
    # as a tenth of the difference being measured, and would change the ratios above if they ran
    # inside their chunks (the field's only in the obstacles' chunks).
    for key, run in runners.items():
        physics[key] = _TimedPhysics(plants[key])
        if key in fields:
            timers[key] = _Timed(fields[key])
        run(PHYSICS_TICKS)
    bare_us = statistics.median(chunks["bare"]) / 1e3
    ticks_run = rounds * CHUNK_TICKS
    figures = {
        "ticks": float(ticks_run),
        "tick_us_bare": bare_us,
        "physics_us_per_tick_bare": physics["bare"].ns / PHYSICS_TICKS / 1e3,
    }
    for key in fields:
        tick_us = statistics.median(chunks[key]) / 1e3
        figures[f"tick_us_{key}"] = tick_us
        figures[f"ratio_{key}"] = tick_us / bare_us
        figures[f"field_us_per_tick_{key}"] = timers[key].ns / PHYSICS_TICKS / 1e3
        figures[f"physics_us_per_tick_{key}"] = physics[key].ns / PHYSICS_TICKS / 1e3
        figures[f"in_influence_{key}"] = float(np.mean(influenced[key]))
    return figures


if __name__ == "__main__":  # pragma: no cover - manual use
    for key, value in bench_obstacles().items():
        print(f"{key}: {value:.3f}")
