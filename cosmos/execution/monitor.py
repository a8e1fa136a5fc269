"""Per-tick judgement of a running segment: done, stopped by UNTIL, failed, or still running.

Evaluated every servo tick (issue: stop conditions and timeouts are checked at
the servo rate), so it works on the estimates the servo already made.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np

from cosmos.plan import (
    ContactTouch,
    DepthReached,
    Elapsed,
    ForceSettled,
    GoalReached,
    Segment,
    SegmentKind,
    condition_holds,
)

FloatArray = np.ndarray


STALL_TIME_S = 2.0
"""A goal motion that gets no closer by STALL_PROGRESS_M for this long has stalled [s]."""
STALL_PROGRESS_M = 0.0005
BLOCKED_N = 2.0
"""A stalled goal motion pushing harder than this [N] is blocked, else out of reach."""
STALL_ACCEPT = 3.0
"""A stall within this many position tolerances of the goal counts as arrival."""


class Verdict(Enum):
    """How a segment ended."""

    DONE = "done"
    STOPPED = "stopped"  # its UNTIL held: success, the statement's remaining segments are skipped
    FAILED = "failed"


@dataclass(frozen=True)
class Outcome:
    """A segment's end: the verdict and why, in words."""

    verdict: Verdict
    reason: str


@dataclass(frozen=True)
class Snapshot:
    """What the monitor looks at in one tick (world axes).

    Attributes:
        t_s: Simulated time, in [s].
        position: Estimated tool point, in [m]. # (3,)
        error: Pose error ``x - x_d`` of the motion command, in [m, rad]. # (6,)
        velocity: Tool twist, in [m/s, rad/s]. # (6,)
        wrench: Wrench the tool applies to the environment, in [N, N m]. # (6,)
    """

    t_s: float
    position: FloatArray
    error: FloatArray
    velocity: FloatArray
    wrench: FloatArray


def _norm3(v: FloatArray) -> float:
    x, y, z = v.tolist()
    return math.sqrt(x * x + y * y + z * z)


def statement_head(statement: str) -> str:
    """The statement's keyword and its first operand, as messages name it (``CONTACT UP``)."""
    words = statement.split()
    return " ".join(words[:2])


class SegmentMonitor:
    """Judges one segment; built when it starts."""

    def __init__(
        self,
        segment: Segment,
        start_s: float,
        start_position: FloatArray,
        statement_start_s: float,
        statement_start_position: FloatArray,
        timed_until_s: float | None,
    ):
        self.segment = segment
        self.start_s = start_s
        self.start_position = start_position
        self.statement_start_s = statement_start_s
        self.statement_start_position = statement_start_position
        self.timed_until_s = timed_until_s
        self._settled_since: float | None = None
        self._closest_m = float("inf")
        self._closest_s = start_s
        self._last_depth = 0.0
        self._last_progress_s = start_s
        rotation = segment.frame_rotation
        self._rotation_t = np.array(rotation).T
        self._motion = np.asarray(segment.motion_axes, dtype=bool)
        self._force_axes = ~self._motion
        # An axis made a spring by COMPLY ... STIFFNESS settles where its spring and the
        # world balance, which need not be the goal: there a stall is an arrival.
        self._sprung = any(
            stiffness is not None and stiffness > 0.0 and moving
            for stiffness, moving in zip(segment.stiffness, self._motion, strict=True)
        )

    def check(self, snap: Snapshot, completion: bool = True) -> Outcome | None:
        """The outcome if the segment ends at this tick, else None.

        Args:
            snap: This tick's estimates.
            completion: False while a MOVE is still on its way through VIA points:
                UNTIL and TIMEOUT are judged, reaching the goal is not.
        """
        seg = self.segment
        force = snap.wrench[:3]
        if seg.until is not None:
            distance = _norm3(snap.position - self.statement_start_position)
            if condition_holds(seg.until, force, snap.wrench[3:], distance):
                return Outcome(Verdict.STOPPED, f"UNTIL {_until_text(seg)} held")
        done = self._completion(snap) if completion else None
        if done is not None:
            return done
        # A CONTACT's TIMEOUT bounds the search for the surface (language.md); once it
        # touched, settling the force has its own bound (ForceSettled.max_time_s).
        timeout = None if seg.kind is SegmentKind.CONTACT_HOLD else seg.timeout_s
        if timeout is not None and snap.t_s - self.statement_start_s >= timeout:
            return Outcome(Verdict.FAILED, self._timeout_reason(timeout))
        return None

    def _timeout_reason(self, timeout_s: float) -> str:
        kind = self.segment.kind
        if kind is SegmentKind.CONTACT_APPROACH:
            return f"found no contact within {timeout_s:g} s"
        if kind is SegmentKind.INSERT:
            return f"timed out after {timeout_s:g} s at depth {self._last_depth * 1e3:.1f} mm"
        return f"timed out after {timeout_s:g} s"

    def _completion(self, snap: Snapshot) -> Outcome | None:
        completion = self.segment.completion
        elapsed = snap.t_s - self.start_s
        if isinstance(completion, GoalReached):
            return self._goal_reached(snap, completion)
        if isinstance(completion, ContactTouch):
            push = float(snap.wrench[:3].dot(completion.direction_world))
            if push > completion.threshold_n:
                return Outcome(Verdict.DONE, f"touched: {push:.2f} N along the approach")
            travel = float((snap.position - self.start_position).dot(completion.direction_world))
            if travel >= completion.max_travel_m - 1e-3:
                return Outcome(
                    Verdict.FAILED, f"found no contact within {completion.max_travel_m * 1e3:.0f} mm"
                )
            return None
        if isinstance(completion, ForceSettled):
            return self._force_settled(snap, completion, elapsed)
        if isinstance(completion, DepthReached):
            return self._depth(snap, completion)
        if isinstance(completion, Elapsed):
            return Outcome(Verdict.DONE, "") if elapsed >= completion.duration_s else None
        return None

    def _goal_reached(self, snap: Snapshot, goal: GoalReached) -> Outcome | None:
        if self.timed_until_s is not None and snap.t_s < self.timed_until_s:
            return None
        r_t = self._rotation_t
        position_error = r_t.dot(snap.error[:3])[self._motion[:3]]
        stalled = self._stalled(snap, float(np.linalg.norm(position_error)), goal)
        if stalled is not None:
            return stalled
        if _norm3(snap.velocity[:3]) > goal.speed_tolerance_mps:
            return None
        rotation_error = r_t.dot(snap.error[3:])[self._motion[3:]]
        if position_error.size and float(np.max(np.abs(position_error))) > goal.position_tolerance_m:
            return None
        if rotation_error.size and float(np.max(np.abs(rotation_error))) > goal.orientation_tolerance_rad:
            return None
        return Outcome(Verdict.DONE, "")

    def _stalled(self, snap: Snapshot, distance_m: float, goal: GoalReached) -> Outcome | None:
        """A goal the arm stopped getting closer to: something in the way, or out of reach.

        Without it a MOVE into the table (or past a joint limit) would push for ever.
        Within a few tolerances of the goal it counts as reached, and says so.
        """
        if distance_m < self._closest_m - STALL_PROGRESS_M:
            self._closest_m, self._closest_s = distance_m, snap.t_s
            return None
        if snap.t_s - self._closest_s < STALL_TIME_S:
            return None
        if distance_m <= STALL_ACCEPT * goal.position_tolerance_m:
            return Outcome(Verdict.DONE, f"settled {distance_m * 1e3:.1f} mm from its goal")
        if self._sprung:
            return Outcome(
                Verdict.DONE, f"settled on its COMPLY spring {distance_m * 1e3:.1f} mm from its goal"
            )
        push = _norm3(snap.wrench[:3])
        short = f"stopped {distance_m * 1e3:.0f} mm short for {STALL_TIME_S:g} s"
        if push > BLOCKED_N:
            return Outcome(
                Verdict.FAILED, f"is blocked: {short}, pushing {push:.1f} N against something in the way"
            )
        return Outcome(Verdict.FAILED, f"cannot reach its goal: {short}, the pose is out of the arm's reach")

    def _force_settled(self, snap: Snapshot, settled: ForceSettled, elapsed: float) -> Outcome | None:
        r_t = self._rotation_t
        wrench_task = np.concatenate((r_t.dot(snap.wrench[:3]), r_t.dot(snap.wrench[3:])))
        error = (wrench_task - self.segment.force_setpoint)[self._force_axes]
        if error.size == 0 or float(np.max(np.abs(error))) <= settled.tolerance_n:
            if self._settled_since is None:
                self._settled_since = snap.t_s
            if snap.t_s - self._settled_since >= settled.settle_time_s:
                return Outcome(Verdict.DONE, "force settled")
        else:
            self._settled_since = None
        if elapsed >= settled.max_time_s:
            # Still pressing, but not steadily (a peg sliding down a chamfer, say): the
            # contact is held, so the statement succeeds and says so; lost, it fails.
            worst = float(np.max(np.abs(error))) if error.size else 0.0
            setpoint = float(np.max(np.abs(self.segment.force_setpoint[self._force_axes])))
            if worst <= 0.5 * setpoint:
                return Outcome(
                    Verdict.DONE,
                    f"contact held, force within {worst:.1f} N of its setpoint but not settled "
                    f"to {settled.tolerance_n:g} N in {settled.max_time_s:g} s",
                )
            return Outcome(Verdict.FAILED, f"force did not settle within {settled.max_time_s:g} s")
        return None

    def _depth(self, snap: Snapshot, depth: DepthReached) -> Outcome | None:
        travelled = float((snap.position - self.start_position).dot(depth.direction_world))
        if travelled >= depth.depth_m:
            return Outcome(Verdict.DONE, f"depth {travelled * 1e3:.1f} mm reached")
        jam = self.segment.jam_check
        if jam is not None:
            if travelled > self._last_depth + jam.stall_speed_mps * jam.stall_time_s:
                self._last_depth = travelled
                self._last_progress_s = snap.t_s
            elif snap.t_s - self._last_progress_s >= jam.stall_time_s:
                push = float(snap.wrench[:3].dot(depth.direction_world))
                return Outcome(
                    Verdict.FAILED,
                    f"jammed at depth {max(travelled, 0.0) * 1e3:.1f} mm: no progress for "
                    f"{jam.stall_time_s:g} s while pushing {push:.1f} N",
                )
        return None


def _until_text(segment: Segment) -> str:
    until = segment.until
    text = getattr(until, "text", None)
    if text:
        return str(text)
    statement = segment.statement
    index = statement.upper().find("UNTIL")
    return statement[index + 5 :].strip() if index >= 0 else "condition"
