"""A segment: one control law until its completion or stop condition, with its INSERT checks."""

from __future__ import annotations

import enum
from dataclasses import dataclass

from cosmos.errors import Span
from cosmos.plan.conditions import Condition
from cosmos.plan.targets import AbsoluteTarget, BoolArray, Completion, FloatArray, SegmentKind, Target

# ---------------------------------------------------------------- segments


@dataclass(frozen=True, eq=False)
class JamCheck:
    """When an INSERT counts as jammed.

    Jammed: the tool moves slower than ``stall_speed_mps`` along the insertion
    direction for ``stall_time_s`` before the depth is reached.
    """

    stall_speed_mps: float
    stall_time_s: float


class ToolEnd(enum.Enum):
    """Where a segment leaves the tool, as far as the program's text says (what the checker follows)."""

    STAYS = "stays"  # a WAIT holding every axis: where it was
    AT_TARGET = "at_target"  # a MOVE holding every axis, without UNTIL: at its target
    UNKNOWN = "unknown"  # a contact, a slide, a spring, an UNTIL: where it ends is not known


class SearchPattern(enum.Enum):
    """The lateral pattern of an INSERT's search (:mod:`cosmos.osc.search`)."""

    SPIRAL = "spiral"
    """Archimedean spiral ``r = pitch theta / 2 pi`` out to the radius."""
    LISSAJOUS = "lissajous"
    """``(r sin(a phi), r sin((a + 1) phi))``, ``a = ceil(pi r / pitch)``, one period."""


@dataclass(frozen=True, eq=False)
class Search:
    """INSERT ... SEARCH: find the hole before inserting.

    From the segment's start the two ``lateral_axes`` are motion-controlled and
    track the pattern (eq. 19) at ``speed_mps`` along its arc, while the insertion
    axis keeps its force. When the tool has gone ``found_depth_m`` along the
    insertion direction beyond where it started, the hole is found: the lateral
    axes return to the segment's compliance and the INSERT goes on. A pattern
    run to its end without that fails the statement.

    Attributes:
        pattern: Spiral or Lissajous.
        radius_m: How far out the pattern goes [m].
        pitch_m: Spiral: the distance between its turns; Lissajous: the largest
            distance between its strands [m].
        lateral_axes: The task-frame translation axes (0..2) of the pattern's x and y.
        speed_mps: Tangential speed along the pattern [m/s].
        found_depth_m: Depth beyond the start that counts as the hole found [m].
    """

    pattern: SearchPattern
    radius_m: float
    pitch_m: float
    lateral_axes: tuple[int, int]
    speed_mps: float
    found_depth_m: float


NAMED_POSTURES = ("home",)
"""Joint configurations a POSTURE may name; the executor takes them from the arm (``home``: its keyframe)."""


@dataclass(frozen=True, eq=False)
class Posture:
    """The joint configuration the null space returns the arm to (POSTURE; seed section 4).

    Attributes:
        joints_rad: The joint angles written [rad], or None for a named pose.
        name: The named pose (one of :data:`NAMED_POSTURES`), or None.
        span: The POSTURE statement (the executor names it when the arm cannot take the pose).
    """

    joints_rad: tuple[float, ...] | None
    name: str | None
    span: Span


@dataclass(frozen=True, eq=False)
class Segment:
    """One control law held until completion, a stop condition, a timeout or a failure.

    Attributes:
        index: Position among the plan's segments, from 0.
        kind: What the segment does.
        statement_index: Counts executed statements from 0; a statement's segments
            share it (procedures and loops expanded, so every call counts anew).
        span: The statement in the source.
        line: ``span.line``.
        statement: The statement's source text.
        context: Where an expanded statement came from ("" at top level), e.g.
            ``"PROC pick called at line 12, REPEAT pass 2 of 3 at line 10"``.
        frame_name: The task frame as written (``"world"`` unless ``IN frame``).
        frame_rotation: Task frame to world rotation, (3, 3).
        motion_axes: Diagonal of the seed's selection matrix Omega, (6,) bool, task
            frame: True = motion-controlled, False = force-controlled (the
            complement selects the force servo).
        force_setpoint: Force then moment the tool applies [N, N m], task frame,
            (6,); zero on motion axes.
        stiffness: Per task axis [N/m x3, N m/rad x3]. ``None`` = the controller's
            default servo stiffness; 0.0 on every force-controlled axis; a COMPLY
            STIFFNESS value on a motion axis makes that axis a spring.
        damping: Per task axis [N s/m x3, N m s/rad x3]; ``None`` = controller default.
        target: Goal of the motion axes: absolute, relative to the pose at segment
            start, or ``None`` = hold the pose measured at segment start.
        via: Intermediate goals passed in order before ``target`` (MOVE TO ... VIA).
        via_radius_m: Switch to the next goal when this close to a via point [m].
        speed_limit_mps: Tool-point speed limit [m/s] (V_max of seed eq. 21); the
            executor also keeps force-controlled axes below it. ``None`` when the
            motion is timed or the segment does not move.
        duration_s: For a timed MOVE (``IN t``): the trajectory's duration [s] (eq. 19).
        completion: How the segment succeeds.
        until: Stop condition (UNTIL): the statement ends with success when it holds.
        timeout_s: The statement fails if not finished this long after it started [s]
            (a CONTACT_HOLD carries its CONTACT's TIMEOUT, which bounds only the
            search for the surface: the hold is bounded by ``ForceSettled.max_time_s``).
        jam_check: INSERT only: when to fail as jammed.
        force_limit_n: The protective stop's force limit in free motion set by the last
            ``LIMIT FORCE`` [N]; None for the executor's default.
        search: INSERT only: the search for the hole before inserting, or None.
        orientation_free: MOVE and WAIT under ORIENTATION FREE: the task controls the
            tool point only, the orientation is left to the null space (seed section 4).
        posture: The POSTURE in force (the null space returns the arm to it), or None.
    """

    index: int
    kind: SegmentKind
    statement_index: int
    span: Span
    line: int
    statement: str
    context: str
    frame_name: str
    frame_rotation: FloatArray
    motion_axes: BoolArray
    force_setpoint: FloatArray
    stiffness: tuple[float | None, ...]
    damping: tuple[float | None, ...]
    target: Target | None
    via: tuple[AbsoluteTarget, ...]
    via_radius_m: float | None
    speed_limit_mps: float | None
    duration_s: float | None
    completion: Completion
    until: Condition | None
    timeout_s: float | None
    jam_check: JamCheck | None
    force_limit_n: float | None = None
    search: Search | None = None
    orientation_free: bool = False
    posture: Posture | None = None

    @property
    def force_axes(self) -> BoolArray:
        """Complement of ``motion_axes``: the diagonal of the force selection matrix."""
        return ~self.motion_axes

    @property
    def tool_end(self) -> ToolEnd:
        """Where the segment leaves the tool, as far as the text says."""
        if not bool(self.motion_axes.all()) or self.until is not None:
            return ToolEnd.UNKNOWN
        if self.kind is SegmentKind.MOVE and any(s is not None and s > 0.0 for s in self.stiffness):
            return ToolEnd.UNKNOWN  # a spring may settle short of its goal, pressing on what stops it
        if self.kind is SegmentKind.WAIT:
            return ToolEnd.STAYS
        return ToolEnd.AT_TARGET if self.kind is SegmentKind.MOVE else ToolEnd.UNKNOWN
