"""The executor's looks at the obstacles during one segment, made at the ticks they can find something.

Among obstacles a servo tick could look at the simulator's contacts for collisions, at the field's
influences (the protective stops leave the path alone while a field acts), and at the share of the
links' field reaching the tool (:class:`~cosmos.execution.field_on_tool.FieldOnToolWatch`). Each of
them changes only at known ticks:

* the collisions are looked for every :data:`~cosmos.execution.obstacles.COLLISION_CHECK_EVERY`
  ticks (:meth:`ObstacleWorld.ticks_to_look`), the executor counting the ticks;
* the field, its influences and the null space's share change at a parameter evaluation (every
  8th tick at 125 Hz: the runtime's :attr:`~cosmos.runtime.loop.Runtime.evaluation` is then a new
  object) or with a new setpoint (a VIA leg's or a SEARCH's, which the executor sets itself): the
  field watch, given the same inputs again, finds what it found; in an episode the ticks between
  its looks keep the tool's largest deviation from its path in the supervisor's compiled call
  (:attr:`~cosmos.execution.supervision.Supervisor.deviation_kept`).

So a tick among obstacles compares a count and an identity.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from cosmos.execution.field_on_tool import FieldOnToolWatch
from cosmos.execution.obstacles import ObstacleWorld
from cosmos.execution.supervision import Supervisor
from cosmos.obstacles.field import Influence
from cosmos.runtime.servo import ServoLevel


class ObstacleTicks:
    """One segment's looks at the obstacle world, the field's influences and the field on the tool.

    Args:
        world: The session's obstacles (some are in the scene).
        servo: The servo level: its null-space terms and obstacle field, as the last evaluation left them.
        supervisor: Told whether a field acts (the path is then not supervised).
        watch: The segment's field-on-tool watch.
        position: The measured tool point, a live view: its distance from the path measured in an episode.
    """

    def __init__(
        self,
        world: ObstacleWorld,
        servo: ServoLevel,
        supervisor: Supervisor,
        watch: FieldOnToolWatch,
        position: np.ndarray,
    ):
        self._world, self._servo, self._supervisor = world, servo, supervisor
        self._watch, self._deviation_m = watch, partial(supervisor.path_deviation_m, position)
        moving = any(obstacle.moving for obstacle in world.scene.obstacles)
        self.move = world.before_tick if moving else None
        """Moves the MOVING obstacles before each tick (:meth:`ObstacleWorld.before_tick`), or None."""
        self.first_look = world.ticks_to_look()
        """The segment's tick (counted from 1) of the first look for collisions; then every
        ``COLLISION_CHECK_EVERY`` ticks."""
        self._looked = 0  # the tick of the last look for collisions
        self._acting: tuple[Influence, ...] = ()  # the influences the supervisor was told of
        supervisor.field_acting = False
        world.before_tick()  # the first tick's: the world's tree rebuilt after an OBSTACLE

    def collisions(self, ticks: int) -> list[str]:
        """At the segment's tick ``ticks``, a look for collisions: the new ones, in words."""
        reasons = self._world.after_tick(ticks - self._looked)
        self._looked = ticks
        return reasons

    def field(self) -> str:
        """A look at the field after an evaluation or a new setpoint: the watch's event, if any."""
        influences = self._world.field.influences
        if influences is not self._acting:
            self._supervisor.field_acting, self._acting = bool(influences), influences
        servo, watch = self._servo, self._watch
        return watch.update(servo.null_space, servo.link_field, self._deviation_m, influences)

    def close(self, ticks: int) -> None:
        """The segment ended at its tick ``ticks``: the world counts the ticks since its last look."""
        if ticks > self._looked:
            self._world.after_tick(ticks - self._looked)
