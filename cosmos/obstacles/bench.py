"""The cost of obstacle avoidance in the servo loop: ticks with 10 obstacles against ticks with none.

Two runtimes, built as the executor builds them (the workcell with its
obstacle slots, the obstacle field installed), make the same goal motions
(from home 400 mm sideways and back, speed limit 0.25 m/s): one with no
obstacle, one among ten (spheres, boxes, posts, a plane, one of them moving),
about four of them within the influence distance at any time. A tick includes everything the executor
does per servo period: moving the obstacles, sensing, the parameter level
(with the field, at its rate), the servo and the physics. The two runs
alternate in short chunks so that the load of a shared machine affects both
alike, and the time measured is this process's CPU time (what other
processes on a shared machine take is not counted); the median chunk is
reported.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

import numpy as np

from cosmos.obstacles.field import ObstacleField
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.obstacles.scene import ObstacleScene, obstacle_scene_xml
from cosmos.plan import ObstacleShape
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

CHUNK_TICKS = 200
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


def _runner(obstacles: tuple[Obstacle, ...]) -> tuple[Runtime, Callable[[int], None], ObstacleField]:
    """A runtime as the executor builds it (workcell with obstacle slots, field installed)."""
    robot = build_robot_model()
    plant = Plant(obstacle_scene_xml())
    runtime = Runtime(plant, robot)
    world = ObstacleScene(plant)
    field = ObstacleField(robot)
    for obstacle in obstacles:
        world.add(obstacle)
        field.add(obstacle)
    runtime.fields.append(field)
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
            world.update(now)
            runtime.tick()

    return runtime, ticks, field


class _Timed:
    """A potential field that adds up the CPU time of the field it wraps."""

    def __init__(self, field: ObstacleField) -> None:
        self.field = field
        self.ns = 0

    def torque(self, q: np.ndarray, qd: np.ndarray, t_s: float) -> np.ndarray:
        start = time.process_time_ns()
        torque = self.field.torque(q, qd, t_s)
        self.ns += time.process_time_ns() - start
        return torque


def bench_obstacles(ticks: int = 4000) -> dict[str, float]:
    """Measure the servo tick with none and with ten obstacles (CPU time; still noisy on a shared machine).

    Args:
        ticks: Servo ticks per configuration (simulated seconds x 1000).

    Returns:
        ``tick_us_none`` and ``tick_us_10`` (median per-tick CPU time of the
        chunks, in microseconds), their ``ratio``, ``field_us_per_tick``
        (CPU time of the field per servo tick, its evaluations spread over the ticks),
        ``mean_obstacles_in_influence`` and ``ticks``.
    """
    _, run_bare, _ = _runner(())
    crowded, run_crowded, field = _runner(bench_scene())
    run_bare(CHUNK_TICKS)  # warm up both (caches, first evaluations)
    run_crowded(CHUNK_TICKS)
    chunks_bare, chunks_crowded, influenced = [], [], []
    timed = _Timed(field)
    crowded.fields[:] = [timed]
    clock = time.process_time_ns  # CPU time of this process: other processes' load does not count
    for _ in range(max(1, ticks // CHUNK_TICKS)):
        start = clock()
        run_bare(CHUNK_TICKS)
        chunks_bare.append((clock() - start) / CHUNK_TICKS)
        start = clock()
        run_crowded(CHUNK_TICKS)
        chunks_crowded.append((clock() - start) / CHUNK_TICKS)
        influenced.append(len(field.influences))
    none_us = statistics.median(chunks_bare) / 1e3
    ten_us = statistics.median(chunks_crowded) / 1e3
    return {
        "ticks": float(len(chunks_bare) * CHUNK_TICKS),
        "tick_us_none": none_us,
        "tick_us_10": ten_us,
        "ratio": ten_us / none_us,
        "field_us_per_tick": timed.ns / (len(chunks_crowded) * CHUNK_TICKS) / 1e3,
        "mean_obstacles_in_influence": float(np.mean(influenced)),
    }


if __name__ == "__main__":  # pragma: no cover - manual use
    for key, value in bench_obstacles().items():
        print(f"{key}: {value:.3f}")
