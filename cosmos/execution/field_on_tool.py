"""When a link's obstacle field reaches the tool although the task leaves a null space: the log says so.

Where the task leaves a null space (ORIENTATION FREE on the PUMA) the servo
applies the links' field through ``N^T`` only, so the tool keeps its path; a
link dangerously close gets the whole field, which moves the tool
(:mod:`cosmos.runtime.null_space`). This watch turns that into two
``field_on_tool`` events: when it begins (the link, the obstacle, its distance,
the share of the field on the tool) and when it ends (the largest deviation of
the tool from its path meanwhile, as the protective stop measures it).

The field on the tool's own link always acts whole: it is the tool's avoidance (seed
section 6), and a WAIT or MOVE it pushes aside is not where the statement holds it. When it
moved the tool more than :data:`MOVED_M` off its path, a ``field_on_tool`` event says how far,
once the field lets go of the tool or the segment ends.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from cosmos.obstacles.field import Influence
from cosmos.runtime.null_space import LinkField, NullSpaceTerms

START_SHARE = 0.1
"""An episode begins when this share of the links' field reaches the tool ..."""
END_SHARE = 0.01
"""... and ends when the share falls below this."""
MOVED_M = 0.001
"""The field on the tool's link moving the tool off its path more than this is told [m]: the
tolerance of an arrival."""


class FieldOnToolWatch:
    """Follows the links' share of the field reaching the tool, one episode at a time.

    Args:
        kept: ``(keeping, largest)``: while the watch sets ``keeping`` (1.0), each tick between
            two looks (:meth:`update`) keeps the tool's largest distance from its path in ``largest``
            [m] (the supervisor's :attr:`~cosmos.execution.supervision.Supervisor.deviation_kept`). # (2,)
    """

    def __init__(self, kept: np.ndarray | None = None) -> None:
        self._kept = np.zeros(2) if kept is None else kept
        self._kept[:] = 0.0
        self._episode: tuple[str, str] | None = None
        self._deviation_m = 0.0
        self._tool_obstacle = ""  # whose field acts on the tool's own link ("": none does)
        self._tool_deviation_m = 0.0
        # The last field looked at, and whether it acts on the tool's link.
        self._field: LinkField | None = None
        self._on_tool = False
        # The influences of the last look, when it found nothing going on (no episode, no obstacle
        # nearest the tool's link): until an evaluation brings another field, share or influences, a
        # look finds nothing again (the executor looks every tick: 0.8-1.2 us a look, 0.2 us this one).
        self._quiet: tuple[Influence, ...] | None = None

    def update(
        self,
        null_space: NullSpaceTerms,
        field: LinkField,
        deviation_m: Callable[[], float],
        influences: tuple[Influence, ...],
    ) -> str:
        """The event's reason when an episode begins or ends, else "".

        Args:
            null_space: The servo's null-space terms at the last evaluation.
            field: The obstacle field as the servo holds it.
            deviation_m: Measures the tool's distance from its path now, in [m].
            influences: The obstacles whose field acts on the arm now.
        """
        if influences is self._quiet and field is self._field and null_space.link_share_to_tool < START_SHARE:
            return ""
        if (  # an episode goes on, the same field: the tool measured (what _links does) and no more
            self._episode is not None
            and field is self._field
            and null_space.link_share_to_tool >= END_SHARE
            and not self._tool_obstacle
        ):
            self._deviation_m = max(self._deviation_m, deviation_m())
            return ""
        self._quiet = None
        self._fold()
        told = self._links(null_space, field, deviation_m)
        if field is not self._field:  # a new field at an evaluation (every 4th tick): looked at once
            self._field, self._on_tool = field, any(field.tool.tolist())
        # The field on the tool's own link (none acts: no look), but not while a link's field
        # reaches the tool: the tool's deviation is then that link's, and told with it (a post
        # holding link 5 back moved the tool 59 mm, told as a far lamp's field on link 7).
        if influences and self._on_tool and self._episode is None:
            if not self._tool_obstacle:  # an obstacle nearest the tool's link (the last: link6 on the PUMA)
                tool_link = f"link{field.tool.shape[0]}"
                self._tool_obstacle = next((i.obstacle for i in influences if i.link == tool_link), "")
            if self._tool_obstacle:
                self._tool_deviation_m = max(self._tool_deviation_m, deviation_m())
                self._keep(self._tool_deviation_m)
            else:  # no obstacle nearest the tool's link: the same inputs find none again
                self._quiet = influences
        elif self._tool_obstacle:
            if self._episode is None:  # else the episode's, from now on
                self._keep(None)
            return "; ".join(reason for reason in (told, self._tool_told()) if reason)
        elif self._episode is None:  # nothing going on: the same inputs find nothing again
            self._quiet = influences
        return told

    def close(self) -> str:
        """At the segment's end: how far the field on the tool's link moved the tool, if it did and untold."""
        self._fold()
        self._keep(None)
        return self._tool_told()

    def _tool_told(self) -> str:
        obstacle, moved = self._tool_obstacle, self._tool_deviation_m
        self._tool_obstacle, self._tool_deviation_m = "", 0.0
        if not obstacle or moved < MOVED_M:
            return ""
        return f"the field of obstacle '{obstacle}' moved the tool up to {moved * 1e3:.1f} mm off its path"

    def _links(self, null_space: NullSpaceTerms, field: LinkField, deviation_m: Callable[[], float]) -> str:
        share = null_space.link_share_to_tool
        if self._episode is None:
            if share < START_SHARE:
                return ""
            self._episode = (field.link, field.obstacle)
            self._deviation_m = deviation_m()
            self._keep(self._deviation_m)
            return (
                f"{field.link} is {field.clearance_m * 1e3:.0f} mm from {field.obstacle}: the null space "
                f"cannot keep it clear, {share:.0%} of its field acts on the tool "
                f"(tool {self._deviation_m * 1e3:.1f} mm off its path)"
            )
        self._deviation_m = max(self._deviation_m, deviation_m())
        if share >= END_SHARE:
            return ""
        link, obstacle = self._episode
        self._episode = None
        self._keep(None)
        return (
            f"{link} clear of {obstacle} through the null space again; the field moved the tool "
            f"up to {self._deviation_m * 1e3:.1f} mm off its path"
        )

    def _keep(self, from_m: float | None) -> None:
        """The ticks keep the tool's largest deviation from ``from_m`` [m] on (None: they stop)."""
        self._kept[:] = (0.0, 0.0) if from_m is None else (1.0, from_m)

    def _fold(self) -> None:
        """The largest deviation the ticks kept since the last look, into the episode's or the tool's."""
        if not self._kept[0]:
            return
        most = float(self._kept[1])
        if self._episode is not None:
            self._deviation_m = max(self._deviation_m, most)
        elif self._tool_obstacle:
            self._tool_deviation_m = max(self._tool_deviation_m, most)
