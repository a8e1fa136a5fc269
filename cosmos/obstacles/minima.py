"""Local minima of the potential field: the goal attracts, an obstacle repels, the arm stops.

The artificial potential field approach does no path planning (seed section
6), so the sum of the goal's attraction and an obstacle's repulsion can have a
minimum away from the goal: the arm comes to rest in front of the obstacle.
:class:`LocalMinimumDetector` watches the distance to the goal; when it has not
shrunk by ``progress_m`` over the last ``window_s`` while the arm is farther
than ``near_goal_m`` from the goal and an obstacle's field is acting, it names
that obstacle, so the statement fails with a message instead of a timeout.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from cosmos.errors import Span, TaskFailure
from cosmos.obstacles.field import Influence


@dataclass(frozen=True)
class LocalMinimum:
    """The arm is stuck in front of an obstacle.

    Attributes:
        obstacle: Name of the obstacle whose field holds the arm (the strongest).
        link: Its nearest link (``link6`` includes the tool).
        distance_to_goal_m: How far the tool is from the goal, in [m].
        t_s: Simulated time of the detection, in [s].
    """

    obstacle: str
    link: str
    distance_to_goal_m: float
    t_s: float

    def message(self, statement: str = "MOVE TO") -> str:
        """E.g. ``MOVE TO stuck in a local minimum ... near obstacle 'wall' (42 mm from the goal)``."""
        return (
            f"{statement} stuck in a local minimum of the potential field near obstacle "
            f"'{self.obstacle}' ({1000.0 * self.distance_to_goal_m:.0f} mm from the goal)"
        )

    def error(self, statement: str = "MOVE TO", span: Span | None = None) -> TaskFailure:
        """The failure to raise for the statement."""
        return TaskFailure(self.message(statement), span)


class LocalMinimumDetector:
    """Call :meth:`update` each tick (or at any steady rate) of one goal motion.

    Args:
        window_s: Time over which progress is judged, in [s].
        progress_m: Least decrease of the distance to the goal over ``window_s``
            that counts as progress, in [m]. Keep it below what the speed limit
            allows in ``window_s`` (a slow move makes little progress by design).
        near_goal_m: Within this distance of the goal the arm is converging, not stuck, in [m].
    """

    def __init__(self, window_s: float = 1.0, progress_m: float = 0.005, near_goal_m: float = 0.01) -> None:
        self.window_s = window_s
        self.progress_m = progress_m
        self.near_goal_m = near_goal_m
        self._history: deque[tuple[float, float]] = deque()

    def reset(self) -> None:
        """Forget the history (a new goal)."""
        self._history.clear()

    def update(
        self, t_s: float, distance_to_goal_m: float, influences: Sequence[Influence]
    ) -> LocalMinimum | None:
        """Record the distance to the goal at ``t_s``; report a local minimum if stuck.

        Args:
            t_s: Simulated time, in [s].
            distance_to_goal_m: Distance from the tool point to the goal, in [m].
            influences: The obstacle field's :attr:`~cosmos.obstacles.ObstacleField.influences`.

        Returns:
            The local minimum, or None while the arm progresses, is near the goal,
            or no obstacle acts on it.
        """
        history = self._history
        history.append((t_s, distance_to_goal_m))
        while len(history) > 1 and history[1][0] <= t_s - self.window_s:
            history.popleft()
        start_s, start_distance = history[0]
        if t_s - start_s < self.window_s or distance_to_goal_m <= self.near_goal_m:
            return None
        if start_distance - distance_to_goal_m > self.progress_m:  # progressing: no obstacle looked at
            return None
        acting = [influence for influence in influences if influence.force_n > 0.0]
        if not acting:
            return None
        strongest = max(acting, key=lambda influence: influence.force_n)
        return LocalMinimum(strongest.obstacle, strongest.link, distance_to_goal_m, t_s)
