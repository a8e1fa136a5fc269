"""The search phase of INSERT ... SEARCH: the pattern's setpoint, and when the hole is found.

While searching, the INSERT's two lateral translations are motion-controlled and
track the pattern (:class:`cosmos.osc.search.SearchTrajectory`) with eq. 19,
``F*_m = xdd_d - kp (x - x_d) - kv (xd - xd_d)``, at the servo's default gains,
while the insertion axis keeps its force (the complement of Omega, as in SLIDE)
and the lateral rotations stay compliant. A pattern offset on the compliant axes'
zero-force setpoint through a spring would do the same with a softer, friction-
dependent lag; a tracked trajectory keeps the tool on the pattern it reports.

The hole is found when the tool has gone ``found_depth_m`` deeper than where the
INSERT started (over the hole's chamfer the force drops it in), or when the compliant
rotations have tipped the part :data:`FIND_TILT` from the orientation the INSERT started
with: its rim over the mouth has dropped in. Dragged on by the pattern, a part so tipped
had its low rim caught on the mouth's inner edge and pulled out sideways (20 N across)
until it knocked free: 260 N, a protective stop, 5.6 mm from a hole it was tipped toward
(SPIRAL RADIUS 16 mm PITCH 5 mm from 12 mm off, seed 0). Dragged on the top face, away from
the mouth, a part tips little (2.9 deg at most in a Panda's spiral from 7.8 mm off, seed 2).
The lateral axes then return to the INSERT's compliance (a new setpoint from the position
there) and the INSERT goes on. A pattern run to its end, and :data:`SETTLE_S` beyond, fails.

The new setpoint keeps the orientation the INSERT started with (:meth:`SearchPhase.resumed_goal`):
the compliant rotations' tilt window (:mod:`cosmos.osc.tilt_window`) is measured from the
setpoint's orientation, and the find comes with the peg tipped into the mouth by its own
compliance, to the window's edge. Taken from the measured pose there, the window was re-centred
on a peg already tipped 10.8 deg, and let it go on to 21 deg: from 5 mm off (a user's
``SEARCH LISSAJOUS RADIUS 8 mm PITCH 3 mm``) it wedged 4.9 mm into the hole on the realistic
plant's seeds 0 and 3 and the ideal plant, and a ``SPIRAL ... PITCH 2 mm`` on seeds 0 and 3
(tests/run/search_grid.py: 74 of its 80 runs inserted before, 78 with the window kept).

**The lead.** The find comes with the part tipped toward the hole (its low rim in the mouth),
its tip up to 4 mm off the hole's axis on the mouth's edge: at zero lateral force it crept
toward the axis at 0.4 mm/s, and the INSERT's jam check (1 s under 0.5 mm/s) failed it 1.5 mm
in (a Panda's SPIRAL PITCH 3 mm from 7.8 mm off, seed 2). The tilt says where the hole is
(:func:`cosmos.osc.search.toward_the_hole`): from the find the lateral axes push toward it at
:data:`LEAD_SHARE` of the INSERT's FORCE, a tilted peg's insertion led by its tip as a person
does it, until the tool is :data:`LEAD_DEPTH_M` deeper than the find, in the bore, whose walls
then centre it (the lateral force back to zero).

**The lead's progress.** Led against the top face's friction, a found part can sink slower than
the INSERT's jam check (0.5 mm/s along the axis for 1 s) while it goes across into the hole. A
Panda's ``SPIRAL RADIUS 12 mm PITCH 3 mm`` from 7.8 mm off at friction 0.52-0.53 (two runs of a
sweep, tests/run/test_run_search_lead.py) found the hole tipped 8 deg toward it, the tip 6.3 and
6.6 mm off its axis, the peg's face on two points of the mouth's edge; led, it crept 1 mm/s across
and 0.3 mm/s deeper, and the jam check failed it 1 s after the find, 0.5 and 0.4 mm in. Left to go
on, it slid in from 4.4 mm off 1.9 s after the find. So did a PUMA's
``programs/search_insert.cos`` at friction 0.70, found 5.2 mm off, jammed 0.9 mm in. So the jam
check waits for the lead too (:attr:`SearchPhase.pattern`), and the lead judges its own progress
at the jam check's rate: its way into the hole, across toward it plus deeper
(:func:`cosmos.osc.search.into_the_hole`), across counted within the pattern's RADIUS of its start
only. Those finds were true, not a part tipped by the top face's friction: in that sweep's six
runs and eight of ``programs/search_insert.cos`` (friction 0.4-0.8) every tilt over 2 deg while
searching pointed within 10 deg of the hole's bearing (within 0.1-6.4 deg at the finds, the tip
3.6-6.6 mm off the axis: the peg's radius is 9.9 mm, the mouth's 11 mm), whether the pattern moved
the tool toward the tilt or against it (their cosine -0.99 to 1.0).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from cosmos.execution.monitor import Outcome, Verdict
from cosmos.execution.resolve import setpoint_for
from cosmos.osc.search import LissajousPath, SearchTrajectory, SpiralPath, into_the_hole, toward_the_hole
from cosmos.plan import DepthReached, Search, SearchPattern, Segment
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

if TYPE_CHECKING:
    from cosmos.runtime.loop import Runtime

FloatArray = np.ndarray

SETTLE_S = 0.5
"""After the pattern's end the tool has this long to drop into a hole it reached last [s]."""
FIND_TILT = math.sin(math.radians(8.0))
"""The hole is found when the part has tipped this far into it (the sine of 8 deg; module docstring)."""
LEAD_SHARE = 0.2
"""The lateral push toward the hole after the find, as a share of the INSERT's FORCE."""
LEAD_MIN_TILT = 0.035
"""No lead from a part tipped less than this (the sine of 2 deg): its direction is noise."""
LEAD_DEPTH_M = 2e-3
"""The lead ends this much deeper than the find [m]: past the mouth's 1 mm chamfer, in the bore."""


class SearchPhase:
    """One INSERT's search, from its start until the hole is found or the pattern ends."""

    def __init__(
        self,
        segment: Segment,
        search: Search,
        start_s: float,
        position: FloatArray,
        rotation: FloatArray,
        runtime: Runtime,
        posture: FloatArray | None = None,
    ):
        self.segment = segment
        self.search = search
        self.name = f"SEARCH {search.pattern.name}"
        lateral = np.array(segment.frame_rotation)[:, list(search.lateral_axes)]
        path = (
            SpiralPath(search.radius_m, search.pitch_m)
            if search.pattern is SearchPattern.SPIRAL
            else LissajousPath.of(search.radius_m, search.pitch_m)
        )
        self.trajectory = SearchTrajectory.of(path, position, rotation, lateral, search.speed_mps)
        self._lateral = lateral
        assert isinstance(segment.completion, DepthReached)  # an INSERT's
        self._direction = segment.completion.direction_world
        self.start_s = start_s
        self.start_position = np.array(position)
        self._start_rotation = np.array(rotation, dtype=float)
        self._farthest_m = 0.0
        self._runtime, self._posture = runtime, posture
        self.found = False
        self.leading = False
        """Found, and pushing toward the hole until :data:`LEAD_DEPTH_M` deeper (:meth:`led`)."""
        self._found_depth_m = 0.0
        self._found_position = np.zeros(3)
        self._toward = np.zeros(3)
        self._lead_mark = (0.0, start_s)
        """The lead's way into the hole when it last progressed [m], and when [s] (:meth:`_lead_jammed`)."""
        # As floats: :meth:`check` runs every servo tick.
        self._start_xyz = tuple(self.start_position.tolist())
        self._direction_xyz = tuple(np.asarray(self._direction, dtype=float).tolist())
        self._lateral_columns = [tuple(column) for column in lateral.T.tolist()]

    def setpoint(self, base: ServoSetpoint) -> ServoSetpoint:
        """The INSERT's setpoint with its lateral translations tracking the pattern."""
        motion = list(base.motion_axes)
        for i in self.search.lateral_axes:
            motion[i] = True
        return replace(
            base,
            mode=MotionMode.TRAJECTORY,
            motion_axes=tuple(motion),
            trajectory=self.trajectory,
            start_s=self.start_s,
        )

    def resumed_goal(self, position: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The INSERT's goal pose once the hole is found: ``position``, the start's orientation."""
        return np.array(position, dtype=float), self._start_rotation.copy()

    def led(self, setpoint: ServoSetpoint, rotation: FloatArray) -> ServoSetpoint:
        """The setpoint after the find with the lateral push toward the hole, if the part is tipped."""
        toward, tilt = toward_the_hole(rotation, self._start_rotation, self._direction, self._lateral)
        if tilt < LEAD_MIN_TILT:
            return setpoint
        self.leading = True
        self._toward = toward
        push = LEAD_SHARE * float(np.linalg.norm(setpoint.force_task[:3]))
        force = np.array(setpoint.force_task, dtype=float)
        force[:3] += setpoint.rotation_task_to_world.T.dot(push * toward)
        return replace(setpoint, force_task=force)

    def lead_over(self, position: FloatArray) -> bool:
        """Whether the lead has taken the tool :data:`LEAD_DEPTH_M` deeper than the find."""
        return self._depth(position) >= self._found_depth_m + LEAD_DEPTH_M

    def _depth(self, position: FloatArray) -> float:
        x, y, z = position.tolist()
        x0, y0, z0 = self._start_xyz
        dx, dy, dz = self._direction_xyz
        return (x - x0) * dx + (y - y0) * dy + (z - z0) * dz

    @property
    def pattern(self) -> SearchPhase | None:
        """Self while the pattern runs or the lead moves the part across, else None.

        The INSERT's jam check (depth alone) waits for both: the lead judges its own progress
        (:meth:`_lead_jammed`).
        """
        return self.going_on

    @property
    def going_on(self) -> SearchPhase | None:
        """Self until the lead after the find is over (or there is none), else None."""
        return self if not self.found or self.leading else None

    def check(self, t_s: float, position: FloatArray, rotation: FloatArray) -> Outcome | str | None:
        """``None`` while searching or leading; the found message once found; a failure at the pattern's end.

        At the find, and at the lead's end, the runtime's setpoint becomes the INSERT's compliance
        (:meth:`resumed_goal`), with the lead (:meth:`led`) at the find.
        """
        if self.found:
            if self.lead_over(position):
                self.leading = False
                self._runtime.set_setpoint(self._resume_setpoint(t_s, position))
                return None
            return self._lead_jammed(t_s, position) if self.leading else None
        found = self._check(t_s, position, rotation)
        if isinstance(found, str):
            self.found = True
            self._found_position = np.array(position, dtype=float)
            self._lead_mark = (0.0, t_s)
            self._runtime.set_setpoint(self.led(self._resume_setpoint(t_s, position), rotation))
        return found

    def _lead_jammed(self, t_s: float, position: FloatArray) -> Outcome | None:
        """A failure if the lead has not taken the part the jam check's way into the hole in its time.

        The way counts across toward the hole and deeper (:func:`cosmos.osc.search.into_the_hole`),
        across only within the pattern's RADIUS of its start, where the user says the hole is.
        """
        jam = self.segment.jam_check
        if jam is None:
            return None
        moved = position - self._found_position
        offset = self._lateral.T.dot(position - self.start_position)
        inside = float(np.hypot(*offset)) <= self.search.radius_m
        made = into_the_hole(moved, self._toward, self._direction, inside)
        mark_m, mark_s = self._lead_mark
        if made > mark_m + jam.stall_speed_mps * jam.stall_time_s:
            self._lead_mark = (made, t_s)
        elif t_s - mark_s >= jam.stall_time_s:
            depth = self._depth(position)
            return Outcome(
                Verdict.FAILED,
                f"jammed at depth {max(depth, 0.0) * 1e3:.1f} mm: led toward the hole, no progress "
                f"across or deeper for {jam.stall_time_s:g} s",
            )
        return None

    def _resume_setpoint(self, t_s: float, position: FloatArray) -> ServoSetpoint:
        rt = self._runtime
        goal = self.resumed_goal(position)
        return setpoint_for(self.segment, *goal, rt.evaluation, rt.wrench, t_s, self._posture)

    def _check(self, t_s: float, position: FloatArray, rotation: FloatArray) -> Outcome | str | None:
        x, y, z = position.tolist()
        x0, y0, z0 = self._start_xyz
        mx, my, mz = x - x0, y - y0, z - z0
        dx, dy, dz = self._direction_xyz
        depth = mx * dx + my * dy + mz * dz
        across = math.sqrt(sum((ax * mx + ay * my + az * mz) ** 2 for ax, ay, az in self._lateral_columns))
        self._farthest_m = max(self._farthest_m, across)
        elapsed = t_s - self.start_s
        tilt = toward_the_hole(rotation, self._start_rotation, self._direction, self._lateral)[1]
        if depth >= self.search.found_depth_m or tilt >= FIND_TILT:
            self._found_depth_m = depth
            how = (
                f"{depth * 1e3:.1f} mm deeper"
                if depth >= self.search.found_depth_m
                else f"tipped {math.degrees(math.asin(min(tilt, 1.0))):.1f} deg into it"
            )
            where = f"{across * 1e3:.1f} mm from the start after {elapsed:.2f} s"
            return f"{self.name} found the hole {where} ({how})"
        if elapsed >= self.trajectory.duration_s + SETTLE_S:
            return Outcome(
                Verdict.FAILED,
                f"{self.name} covered {self.search.radius_m * 1e3:g} mm without finding the hole: "
                f"out to {self._farthest_m * 1e3:.1f} mm from its start in {elapsed:.1f} s, never "
                f"{self.search.found_depth_m * 1e3:g} mm deeper",
            )
        return None


def search_phase(
    segment: Segment,
    start_s: float,
    position: FloatArray,
    rotation: FloatArray,
    runtime: Runtime,
    posture: FloatArray | None = None,
) -> SearchPhase | None:
    """The segment's search phase, if it has one (it sets ``runtime``'s setpoints after the find)."""
    if segment.search is None:
        return None
    return SearchPhase(segment, segment.search, start_s, position, rotation, runtime, posture)
