"""The executor's side of OBSTACLE: bodies in the workcell, the FIRAS field, minima, collisions.

One :class:`ObstacleWorld` per session ties together what ``cosmos.obstacles``
provides: each added obstacle becomes a body in the MuJoCo workcell (so a
collision is a real contact) and a term of the repulsive field the runtime
adds at its parameter rate (seed section 6), and is drawn on the log's
``/scene``; every tick moving obstacles move, contacts the arm should not make
are logged as ``collision`` events, and a goal motion that stops progressing
while obstacles act on the arm is reported as a local minimum.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.errors import TaskFailure
from cosmos.execution.float_maths import distance_to_point
from cosmos.execution.monitor import JUDGE_MOVING_EVERY
from cosmos.obstacles import (
    ContactGate,
    LocalMinimum,
    LocalMinimumDetector,
    Obstacle,
    ObstacleField,
    ObstacleScene,
    collisions,
    from_step,
)
from cosmos.osc.orientation import matrix_to_quat
from cosmos.plan import AddObstacle, ObstacleShape, RemoveObstacle
from cosmos.runlog.scene import Box, Cylinder, Primitive, Sphere
from cosmos.runlog.writer import RunLog
from cosmos.runtime.loop import Runtime

COLLISION_CHECK_EVERY = 10
"""Ticks between two looks at the simulator's contacts for collisions (10 ms at 1 kHz)."""

SCENE_EVERY = 4 * COLLISION_CHECK_EVERY
"""Ticks between two updates of moving obstacles on ``/scene`` (25 Hz at 1 kHz)."""

MINIMUM_CHECK_EVERY = JUDGE_MOVING_EVERY
"""Ticks between two looks for a local minimum (25 ms at 1 kHz, against the detector's 1 s
window), as a stall is judged; every tick it cost a goal motion among obstacles 1-2 us a tick."""

PLANE_DRAWN_SIZE_M = 2.0
"""A plane is drawn as a thin square of this side."""


def primitive(obstacle: Obstacle, t_s: float) -> Primitive:
    """How an obstacle is drawn in the log's 3-D scene."""
    position = obstacle.position_at(t_s).tolist()
    if obstacle.shape is ObstacleShape.SPHERE:  # no orientation drawn
        return Sphere(obstacle.name, position, obstacle.radius_m)
    quat = matrix_to_quat(obstacle.rotation_world).tolist()
    if obstacle.shape is ObstacleShape.CYLINDER:
        height = 2.0 * float(obstacle.half_extents_m[2])
        return Cylinder(obstacle.name, position, obstacle.radius_m, height, quat)
    if obstacle.shape is ObstacleShape.BOX:
        return Box(obstacle.name, position, (2.0 * obstacle.half_extents_m).tolist(), quat)
    return Box(obstacle.name, position, (PLANE_DRAWN_SIZE_M, PLANE_DRAWN_SIZE_M, 0.002), quat)


class ObstacleWorld:
    """Obstacles of one session, on the plant, in the runtime's field and in the log."""

    def __init__(self, runtime: Runtime, log: RunLog | None):
        self.runtime = runtime
        self.log = log
        self.scene = ObstacleScene(runtime.plant)
        self.field = ObstacleField(runtime.robot)
        self.gate = ContactGate(runtime.plant, self.scene.version)
        # The field joins the runtime's parameter level with the first obstacle and leaves it
        # with the last, and the contact gate its physics steps: a tick without obstacles costs
        # what a bare tick costs.
        self.detector = LocalMinimumDetector()
        self._data = runtime.plant.data  # its contacts and clock, looked at in the servo loop
        self._moving: tuple[Obstacle, ...] = ()  # the scene's MOVING obstacles, redrawn as they move
        self._touching: set[tuple[str, str]] = set()
        self._ticks = 0
        self._goal_ticks = 0  # ticks of the goal motion under way

    @property
    def active(self) -> bool:
        """Whether any obstacle is in the scene."""
        return bool(self.scene.obstacles)

    def apply(self, step: AddObstacle | RemoveObstacle) -> None:
        """Add or remove an obstacle (the compiler has checked names and shapes)."""
        t_s = self.runtime.time_s
        self.gate.release()  # every body collides again: the overlap check below, and the next step
        if isinstance(step, AddObstacle):
            obstacle = from_step(step, t_s)
            self.scene.add(obstacle)
            overlap = self._overlap(step.name)
            if overlap:
                self.scene.remove(step.name)
                raise TaskFailure(
                    f"OBSTACLE {step.name} would be placed through the arm ({overlap})",
                    step.span,
                )
            self.field.add(obstacle)
            self._attach_field()
            if self.log is not None:
                self.log.scene(t_s, add=[primitive(obstacle, t_s)])
        else:
            self.scene.remove(step.name)
            self.field.remove(step.name)
            self._attach_field()
            if self.log is not None:
                self.log.scene(t_s, remove=[step.name])
        self._moving = tuple(obstacle for obstacle in self.scene.obstacles if obstacle.moving)

    def _attach_field(self) -> None:
        """The field in the parameter level and the gate on the steps while any obstacle is in the scene."""
        fields = self.runtime.fields
        attached = any(field is self.field for field in fields)
        if self.active and not attached:
            fields.append(self.field)
            self.runtime.contact_gate = self.gate
        elif not self.active and attached:
            fields.remove(self.field)
            self.runtime.contact_gate = None
            servo = self.runtime.servo
            servo.field_torque = np.zeros_like(servo.field_torque)  # nothing pushes any more

    def _overlap(self, name: str) -> str:
        """The arm's bodies the obstacle ``name`` overlaps where the arm is now ("" if none)."""
        plant = self.runtime.plant
        mujoco.mj_kinematics(plant.model, plant.data)
        mujoco.mj_collision(plant.model, plant.data)
        touching = [c.arm_body for c in collisions(plant, self.scene.body_names()) if c.other == name]
        return ", ".join(f"{body} inside it" for body in sorted(set(touching)))

    def before_tick(self) -> None:
        """Move the moving obstacles to where they are now (the first tick after an OBSTACLE: the tree)."""
        self.scene.update(self._data.time)  # every tick among moving obstacles: no property on the way

    def ticks_to_look(self) -> int:
        """How many ticks from now the tick is whose :meth:`after_tick` looks for collisions (1: the next)."""
        return COLLISION_CHECK_EVERY - self._ticks % COLLISION_CHECK_EVERY

    def after_tick(self, ticks: int = 1) -> list[str]:
        """``ticks`` more ticks ran: new collisions, and moving obstacles redrawn, if a look falls due now.

        A look is due every :data:`COLLISION_CHECK_EVERY` ticks (:meth:`ticks_to_look`). Returns reasons.
        """
        self._ticks += ticks
        if self._ticks % COLLISION_CHECK_EVERY:  # SCENE_EVERY is a multiple of it
            return []
        if self._moving and self.log is not None and self._ticks % SCENE_EVERY == 0:
            t_s = self._data.time
            self.log.scene(t_s, add=[primitive(obstacle, t_s) for obstacle in self._moving])
        if not self._data.ncon:  # no contact: no collision (the scene's names not gathered for nothing)
            self._touching.clear()
            return []
        plant = self.runtime.plant
        found = {(c.arm_body, c.other) for c in collisions(plant, self.scene.body_names())}
        new = sorted(found - self._touching)
        self._touching = found
        return [f"{arm} touches {other}" for arm, other in new]

    def start_goal(self) -> None:
        """A goal motion begins: forget the progress of the previous one."""
        self.detector.reset()
        self._goal_ticks = 0

    def local_minimum(
        self, position: np.ndarray, goal: tuple[float, ...], ticks: int = 1
    ) -> LocalMinimum | None:
        """The local minimum the goal motion is stuck in, if any (looked for every few ticks).

        Every :data:`MINIMUM_CHECK_EVERY` ticks of the goal motion: the detector takes any steady rate.

        Args:
            position: The measured tool point, world [m]. # (3,)
            goal: The goal point, world [m].
            ticks: Ticks of the goal motion since the last call (a caller may call only when a look is due).
        """
        self._goal_ticks += ticks
        if self._goal_ticks % MINIMUM_CHECK_EVERY or not self.active:
            return None
        distance_m = distance_to_point(position, goal)
        return self.detector.update(self._data.time, distance_m, self.field.influences)
