"""Per-tick judgement of a running segment: done, stopped by UNTIL, failed, or still running.

Evaluated every servo tick. Arrival is judged on the measured tool pose, position and
orientation both (:mod:`cosmos.execution.arrival`), once the tool has settled there; a timed
move (``IN t``) ends only on arrival, and fails with the measured error if it has not arrived
:data:`TIMED_SETTLE_S` after its time; a CONTACT's approach that stands short of its touch
has landed or is held back (:mod:`cosmos.execution.approach_stall`).
The measurements a tick is judged on are a :class:`~cosmos.execution.snapshot.Snapshot` (re-exported).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

import numpy as np

from cosmos.execution import approach_stall, lost_push, touch_push
from cosmos.execution.approach_stall import approach_state, timeout_reason
from cosmos.execution.arrival import REST_ANGULAR_SPEED_RAD_S, GoalError
from cosmos.execution.closing import Closing, stall_reason
from cosmos.execution.conditions import condition_text, measured_text, reads_grip
from cosmos.execution.float_maths import length_along, norm3, pose_error
from cosmos.execution.goal_gate import GoalGate
from cosmos.execution.left_surface import watched
from cosmos.execution.listing import Listing, entry
from cosmos.execution.lost_push import hold_ended, hold_state, lost_surface
from cosmos.execution.snapshot import Snapshot
from cosmos.execution.supervision import ProtectiveStop
from cosmos.lang.check.limits import MAX_DURATION_S
from cosmos.osc.orientation import unwrap_rotation_vector
from cosmos.plan import (
    ContactTouch,
    DepthReached,
    Elapsed,
    ForceSettled,
    GoalReached,
    Segment,
    SegmentKind,
    UntilOnly,
    condition_holds,
)

FloatArray = np.ndarray
__all__ = ["Outcome", "SegmentMonitor", "Snapshot", "Verdict"]

STALL_ANGLE_SCALE_M = 0.1
"""Progress in orientation counts as this many metres per radian."""
JUDGE_MOVING_EVERY = 25
"""While the tool moves, its error (a stall's 2 s, an overrun's 1 s) is judged every this many ticks."""
SETTLE_S = 0.02
"""The tool must stay within tolerance and at rest this long to have arrived [s]."""
TIMED_SETTLE_S = 1.0
"""A timed move that has not arrived this long after its duration fails [s]."""


class Verdict(Enum):
    """How a segment ended."""

    DONE = "done"
    STOPPED = "stopped"  # its UNTIL held: success, the statement's remaining segments are skipped
    FAILED = "failed"


@dataclass(frozen=True)
class Outcome:
    """A segment's end: the verdict and why, in words; a stop's details; whether an approach touched."""

    verdict: Verdict
    reason: str
    stop: ProtectiveStop | None = None
    touched: bool = False


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
        goal: tuple[FloatArray, FloatArray],
        stall_cause: Callable[[], str],
        tool_mass_kg: float = 0.0,
    ):
        self.segment = segment
        self.goal_position, self.goal_rotation = goal
        self.stall_cause = stall_cause
        self.start_s = start_s
        self.start_position = start_position
        self.statement_start_s = statement_start_s
        self.statement_start_position = statement_start_position
        self.timed_until_s = timed_until_s
        self._reads_grip = segment.until is not None and reads_grip(segment.until)
        self._settled_since: float | None = None
        self.turn_long_way = False
        """Set when the controller turns the long way round to the goal orientation."""
        self.tool_touched: Callable[[], bool] = lambda: True  # a fixture, since the segment started
        self._tool_mass_kg = tool_mass_kg  # the tool's inertia is no touch (cosmos.execution.touch_push)
        self._turn: tuple[float, ...] | None = None
        self._turn_angle, self._closing = 0.0, Closing(since_s=start_s)
        self._last_depth, self._last_progress_s = 0.0, start_s
        self.searching: object | None = segment.search
        """An INSERT's search still under way (cosmos.execution.search): no jam check meanwhile."""
        rotation = segment.frame_rotation
        self._rotation_t = np.array(rotation).T
        self._motion = np.array(segment.motion_axes, dtype=bool)
        if segment.orientation_free:  # ORIENTATION FREE: the orientation is not the goal's
            self._motion[3:] = False
        self._force_axes = ~self._motion
        # The TIMEOUT in force: a CONTACT's bounds the search for the surface (language.md); once it
        # touched, its hold has its own bounds (ForceSettled.max_time_s, a lost contact's 15 mm).
        timeout = None if segment.kind is SegmentKind.CONTACT_HOLD else segment.timeout_s
        if timeout is None and isinstance(segment.completion, UntilOnly):
            timeout = MAX_DURATION_S  # WAIT UNTIL without TIMEOUT: bounded all the same
        self._timeout_s = timeout
        self._deadline_s = math.inf if timeout is None else statement_start_s + timeout - 1e-9
        # An axis made a spring by COMPLY ... STIFFNESS settles where its spring and the
        # world balance, which need not be the goal: there a stall is an arrival.
        # The goal point and the task frame's motion-controlled translation axes (rows of R^T), as
        # floats: a slow tool off its goal point is told apart every tick at the cost of a few products.
        self._goal_xyz: tuple[float, ...] = tuple(np.asarray(self.goal_position, dtype=float).tolist())
        self._position_rows = [tuple(row) for row in self._rotation_t[self._motion[:3]].tolist()]
        self._rotation_rows = [tuple(row) for row in self._rotation_t[self._motion[3:]].tolist()]
        self._goal_rows = tuple(tuple(row) for row in np.asarray(self.goal_rotation, dtype=float).tolist())
        direction = getattr(segment.completion, "direction_world", None)  # a touch's or a depth's
        self._direction: tuple[float, ...] = (0.0,) * 3 if direction is None else tuple(direction.tolist())
        self._start_xyz: tuple[float, ...] = tuple(np.asarray(start_position, dtype=float).tolist())
        self._statement_xyz = tuple(np.asarray(statement_start_position, dtype=float).tolist())
        self._sprung = any(
            stiffness is not None and stiffness > 0.0 and moving
            for stiffness, moving in zip(segment.stiffness, self._motion, strict=True)
        )
        self._in_time = False  # whether the ending's judge finds the TIMEOUT's deadline too
        self._complete = self._completion_judge(segment.completion)  # chosen once: it runs every tick
        self._turns = bool(self._motion[3:].any())
        self.judge: Callable[[Snapshot], Outcome | None] = (
            self.check
            if segment.until is not None
            else self._complete_in_time
            if timeout is not None and not self._in_time
            else self._complete
        )
        """Judges a tick of the last leg: :meth:`check`, or without UNTIL the segment's own ending and
        its TIMEOUT, or that ending alone (no UNTIL, no TIMEOUT; or a compiled judge that finds its
        TIMEOUT's deadline too): one call a tick, not two."""
        ending, until = segment.completion, timed_until_s  # a timed goal motion's arrival: from its time
        until = start_s + ending.duration_s - 1e-9 if isinstance(ending, Elapsed) else until  # a WAIT's end
        alone = self.judge == self._goal_reached or self.judge is self._complete and type(ending) is Elapsed
        self.idle_until_s = until if alone and until is not None else -math.inf
        """Before this time :attr:`judge` finds nothing and changes nothing (1e-9 s early for rounding)."""
        self.gate = self._gate if self.judge == self._goal_reached else None
        """Where :attr:`judge` is a goal motion's alone: its gate (a tick it passes by, :attr:`judge`
        does too), and :attr:`judged` the judge of the ticks it does not (cosmos.execution.goal_gate)."""
        self.judged = self._goal_judged

    def check(self, snap: Snapshot, completion: bool = True) -> Outcome | None:
        """The outcome if the segment ends at this tick, else None.

        Args:
            snap: This tick's estimates.
            completion: False while a MOVE is still on its way through VIA points:
                UNTIL and TIMEOUT are judged, reaching the goal is not.
        """
        seg = self.segment
        if seg.until is not None:
            force = snap.wrench[:3]
            distance = norm3(snap.position - self.statement_start_position)
            grip = snap.grip() if self._reads_grip else 0.0  # read once: the value told is the one that fired
            if condition_holds(seg.until, force, snap.wrench[3:], distance, grip):
                measured = measured_text(seg.until, force, snap.wrench[3:], distance, grip)
                return Outcome(
                    Verdict.STOPPED, f"UNTIL {condition_text(seg.until)}: {measured} at {snap.t_s:.2f} s"
                )
        if completion:
            done = self._complete(snap)
            if done is not None:
                return done
        return self._timed_out(snap) if snap.t_s >= self._deadline_s else None

    def _complete_in_time(self, snap: Snapshot) -> Outcome | None:
        """:meth:`check` of a segment without UNTIL: its own ending, then its TIMEOUT."""
        done = self._complete(snap)
        return self._timed_out(snap) if done is None and snap.t_s >= self._deadline_s else done

    def _timed_out(self, snap: Snapshot) -> Outcome | None:
        """The TIMEOUT's failure once ``snap`` is past its deadline (as written, to the tick)."""
        if self._timeout_s is not None and snap.t_s - self.statement_start_s >= self._timeout_s:
            return Outcome(
                Verdict.FAILED, timeout_reason(self.segment.kind, self._timeout_s, self._last_depth)
            )
        return None

    def _completion_judge(self, completion: object) -> Callable[[Snapshot], Outcome | None]:
        """The judge of the segment's own ending (``completion``), one snapshot at a time."""
        if isinstance(completion, GoalReached):
            self._goal = completion  # a SLIDE's is watched for leaving its surface (execution.left_surface)
            self._gate = GoalGate(
                self._goal_xyz, completion.speed_tolerance_mps, completion.position_tolerance_m,
                self._position_rows, JUDGE_MOVING_EVERY,
            )  # fmt: skip
            return watched(self.segment, self._start_xyz, self._goal_reached, Verdict.FAILED, Outcome)
        # A CONTACT's approach and hold: one compiled call a tick on self._state (its deadline without UNTIL).
        deadline_s, self._in_time = (
            (self._deadline_s, True) if self.segment.until is None else (math.inf, False)
        )
        if isinstance(completion, ContactTouch):
            self._state = approach_state(
                self.segment, self._start_xyz, self.start_s, self._tool_mass_kg, deadline_s
            )
            return self._compiled(Listing(self._state), entry(approach_stall.approach), self._touch_ended)
        if isinstance(completion, ForceSettled):
            self._state = hold_state(
                self.segment, self._force_axes, self._start_xyz, self.start_s, deadline_s
            )
            return self._compiled(Listing(self._state), entry(lost_push.hold), self._hold_ended)
        self._in_time = False
        # The judges below read their ending from self: one call a tick, no wrapper.
        if isinstance(completion, DepthReached):
            self._depth_ending = completion
            if completion.touch_n is not None:  # an INSERT's approach: it ends where the tool touches
                speed, direction = self.segment.speed_limit_mps, self._direction
                state = touch_push.insert_touch(self._tool_mass_kg, speed, direction, completion.touch_n)
                self._insert, self._insert_touched = Listing(state), entry(touch_push.insert_touched)
            return self._depth
        if isinstance(completion, Elapsed):
            duration_s = completion.duration_s
            return lambda snap: Outcome(Verdict.DONE, "") if snap.t_s - self.start_s >= duration_s else None
        return lambda snap: None

    @staticmethod
    def _compiled(
        listing: Listing, found_at: Callable[..., int], ended: Callable[[int, Snapshot], Outcome | None]
    ) -> Callable[[Snapshot], Outcome | None]:
        """A judge calling compiled ``found_at(table, t_s)`` on ``listing``; ``ended`` once it finds."""
        table = listing.table

        def judge(snap: Snapshot) -> Outcome | None:
            if snap is not listing.snapshot:  # a new snapshot, or arrays copied every tick
                listing.list(snap)
            found = found_at(table, snap.t_s)
            return ended(found, snap) if found else None

        return judge

    def _touch_ended(self, found: int, snap: Snapshot) -> Outcome | None:
        """What a CONTACT's approach that found ``found`` (cosmos.execution.approach_stall) ends with."""
        if found == approach_stall.DEADLINE_PASSED:
            return self._timed_out(snap)
        ended = approach_stall.ended(found, self._state, self.stall_cause)
        if ended is None:
            return None
        done, touched, reason = ended
        return Outcome(Verdict.DONE if done else Verdict.FAILED, reason, touched=touched)

    def _hold_ended(self, found: int, snap: Snapshot) -> Outcome | None:
        """What a held push that found ``found`` (cosmos.execution.lost_push) ends with."""
        if found == lost_push.DEADLINE_PASSED:
            return self._timed_out(snap)
        ended = hold_ended(found, self._state, self.segment, self._force_axes, snap.t_s)
        return None if ended is None else Outcome(Verdict.DONE if ended[0] else Verdict.FAILED, ended[1])

    def _goal_reached(self, snap: Snapshot) -> Outcome | None:
        timed = self.timed_until_s
        if timed is not None and snap.t_s < timed:
            return None
        gate = self._gate  # on its way (too fast, or slow but off its goal point): passed by, compiled
        if gate.listed(gate.table) if snap is gate.snapshot else gate.passes(snap):
            return None
        return self._goal_judged(snap)

    def _goal_judged(self, snap: Snapshot) -> Outcome | None:
        """A goal motion's tick its gate did not pass by: maybe arrived, or one to judge the whole error."""
        goal, timed = self._goal, self.timed_until_s
        if self._gate.settling_broken():  # a tick passed by since the last: not arrived then
            self._settled_since = None
        vx, vy, vz, wx, wy, wz = snap.velocity.tolist()
        speed = math.sqrt(vx * vx + vy * vy + vz * vz)
        # The error in floats (a 3 x 3 product and a log: 3 us, where arrays cost 10-25 us).
        (ex, ey, ez), turned = pose_error(
            snap.position.tolist(), snap.rotation.tolist(), self._goal_xyz, self._goal_rows
        )
        rx, ry, rz = turned
        # The error's length on the motion axes (a force axis's position is the force's):
        # "1 mm and 1 deg" as the reason reports them.
        position_off = length_along(self._position_rows, ex, ey, ez)
        rotation_off = length_along(self._rotation_rows, rx, ry, rz)
        arrived = (
            speed <= goal.speed_tolerance_mps
            and length_along(self._rotation_rows, wx, wy, wz) <= REST_ANGULAR_SPEED_RAD_S
            and position_off <= goal.position_tolerance_m
            and rotation_off <= goal.orientation_tolerance_rad
        )
        if arrived:
            if self._settled_since is None:
                self._settled_since = snap.t_s
            if snap.t_s - self._settled_since >= SETTLE_S - 1e-9:
                off = f"{position_off * 1e3:.1f} mm"
                if self.segment.orientation_free:
                    return Outcome(Verdict.DONE, f"arrived: {off} from its goal, orientation free")
                return Outcome(
                    Verdict.DONE, f"arrived: {off} and {math.degrees(rotation_off):.1f} deg from its goal"
                )
            return None
        self._settled_since = None
        if timed is not None and snap.t_s >= timed + TIMED_SETTLE_S and not self._sprung:  # springs: stall
            duration = timed - self.start_s  # an IN t's, or what its SPEED takes (SLIDE, a slow MOVE)
            took = (
                f"its {duration:g} s" if self.segment.duration_s else f"the {duration:.3g} s its SPEED takes"
            )
            off = f"{position_off * 1e3:.1f} mm and {math.degrees(rotation_off):.1f} deg from its goal"
            why = f"did not arrive within {TIMED_SETTLE_S:g} s after {took}: {off}"  # on the motion axes
            return Outcome(Verdict.FAILED, why + lost_surface(self.segment, self._start_xyz, snap.position))
        # Turning the long way round (cosmos.runtime.rotation_plan) the shortest angle first
        # grows: progress counts the rotation left the way the arm turns (kept continuous).
        angle = math.sqrt(rx * rx + ry * ry + rz * rz)
        left: tuple[float, ...] = turned
        if not self._turns:  # no orientation to make progress in
            left, angle = (0.0, 0.0, 0.0), 0.0
        elif self._turn is None:
            if self.turn_long_way and angle > 1e-3:
                scale = 1.0 - 2.0 * math.pi / angle
                left = (rx * scale, ry * scale, rz * scale)
                angle = math.sqrt(left[0] * left[0] + left[1] * left[1] + left[2] * left[2])
        elif angle + self._turn_angle >= math.pi - 0.1:  # else the short way is by far the nearer:
            left = tuple(unwrap_rotation_vector(np.array(turned), np.array(self._turn)).tolist())
            angle = math.sqrt(left[0] * left[0] + left[1] * left[1] + left[2] * left[2])
        self._turn, self._turn_angle = left, angle
        return self._stalled(snap, position_off + STALL_ANGLE_SCALE_M * angle, (ex, ey, ez), turned)

    def _stalled(
        self, snap: Snapshot, distance_m: float, off: tuple[float, ...], turned: tuple[float, ...]
    ) -> Outcome | None:
        """A goal the arm stopped getting closer to (a MOVE into the table would push on): error, cause."""
        if not self._closing.stalled(distance_m, snap.t_s):
            return None
        error = GoalError(np.array(off), np.array(turned))
        if self._sprung:
            return Outcome(
                Verdict.DONE, f"settled on its COMPLY spring {error.distance_m * 1e3:.1f} mm from its goal"
            )
        speed = norm3(snap.velocity[:3])
        rest = self._goal.speed_tolerance_mps
        return Outcome(Verdict.FAILED, stall_reason(error.text(), speed, rest, self.stall_cause))

    def _depth(self, snap: Snapshot) -> Outcome | None:
        depth = self._depth_ending
        dx, dy, dz = self._direction
        x, y, z = snap.position.tolist()
        x0, y0, z0 = self._statement_xyz  # DEPTH counts from the statement's start
        travelled = (x - x0) * dx + (y - y0) * dy + (z - z0) * dz
        if depth.touch_n is not None:  # an INSERT's approach: it ends where the tool touches
            if snap is not self._insert.snapshot:
                self._insert.list(snap)
            if self._insert_touched(self._insert.table, snap.t_s):
                return Outcome(
                    Verdict.DONE, f"touched: {self._insert.state[touch_push.PUSH]:.2f} N", touched=True
                )
            if travelled < depth.depth_m:
                return None
            if not self.tool_touched():  # a part entering its hole meets the chamfer or the bore
                return Outcome(Verdict.FAILED, f"went its DEPTH of {travelled * 1e3:.1f} mm touching nothing")
        if travelled >= depth.depth_m:
            return Outcome(Verdict.DONE, f"depth {travelled * 1e3:.1f} mm reached")
        jam = self.segment.jam_check
        if self.searching is not None:  # the pattern moves across: depth is the search's to judge
            self._last_depth, self._last_progress_s = travelled, snap.t_s
        elif jam is not None:
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
