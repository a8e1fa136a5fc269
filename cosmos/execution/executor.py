"""Runs a compiled plan on the runtime, segment by segment, and logs what happened.

Each segment starts from the measured state: the parameters are re-evaluated,
relative targets resolved against the measured pose, and force setpoints ramp
from the sensed force, so there is no jump at a switch between motion and
force control. Stop conditions, completion and timeouts are judged every servo
tick, on the measured tool pose (:mod:`cosmos.execution.arrival`), and so are
the protective stops (:mod:`cosmos.execution.supervision`). A failed statement
leaves the arm holding its pose (all axes under position control, no force
commanded), writes a ``failed`` event (after a ``protective_stop`` one, and a
``collision`` one, where it was that), and raises
:class:`~cosmos.errors.TaskFailure` naming the statement and the reason.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import NoReturn

import numpy as np

from cosmos.errors import TaskFailure
from cosmos.execution.arrival import ToolMeter, goal_error, out_of_reach, singularity, stall_cause
from cosmos.execution.expected import free_limit_n
from cosmos.execution.field_on_tool import FieldOnToolWatch
from cosmos.execution.float_maths import distance_to_point
from cosmos.execution.holding import brake_after_until, hold_pose
from cosmos.execution.monitor import Outcome, SegmentMonitor, Snapshot, Verdict
from cosmos.execution.obstacle_ticks import ObstacleTicks
from cosmos.execution.obstacles import COLLISION_CHECK_EVERY, MINIMUM_CHECK_EVERY, ObstacleWorld
from cosmos.execution.recording import LogRecorder, log_segment
from cosmos.execution.resolve import posture_joints, segment_goals, setpoint_for
from cosmos.execution.search import search_phase
from cosmos.execution.supervision import StopKind, Supervisor
from cosmos.execution.tare import FreeAir
from cosmos.execution.via_legs import ViaProgress
from cosmos.execution.walker import NO_HAND, HandSteps, PlanWalker, Senses
from cosmos.execution.wording import failure_text, origin, statement_head
from cosmos.lang.check.limits import timed_move_problem
from cosmos.plan import (
    AddObstacle,
    GoalReached,
    Plan,
    RemoveObstacle,
    Segment,
    SegmentKind,
    Step,
)
from cosmos.runlog.writer import RunLog
from cosmos.runtime.landing_zone import with_landing
from cosmos.runtime.loop import Runtime
from cosmos.runtime.setpoint import ServoSetpoint
from cosmos.workcell import home_q

HOLD_AFTER_FAILURE_S = 0.3
"""After a failure the arm holds its pose this long before the run ends [s]."""


class Interrupted(TaskFailure):
    """The run was stopped from outside (Ctrl-C, SIGTERM)."""


@dataclass(frozen=True)
class Progress:
    """What a progress display shows: the statement running and the simulated time."""

    line: int
    statement: str
    t_s: float


ProgressCallback = Callable[[Progress], None]
EventCallback = Callable[[str, Step, str, str], None]  # kind, step, reason, context: the REPL's echo


class Executor:
    """Executes plans on one runtime; state (pose, held contact) persists across plans."""

    def __init__(
        self,
        runtime: Runtime,
        log: RunLog | None = None,
        progress: ProgressCallback | None = None,
        progress_every: int = 200,
        obstacles: ObstacleWorld | None = None,
    ):
        self.runtime = runtime
        self.log = log
        self.progress = progress
        self.progress_every = progress_every
        self.stop_requested = False
        self.on_event: EventCallback | None = None
        self.recorder: LogRecorder | None = None
        if log is not None:
            self.recorder = LogRecorder(log, runtime.plant, runtime.robot.description.frames)
            runtime.recorder = self.recorder
        self.obstacles = obstacles
        self.hand: HandSteps = NO_HAND  # the gripper's GRASP and RELEASE (TOOL GRIPPER)
        self.segment_count = 0
        self._source: str | None = None
        self._tool = "peg"  # the plan's TOOL: a CONTACT's landing (cosmos.runtime.landing_zone)
        self._stopped_at: float | None = None
        self.free_air = FreeAir()  # the wrist sensor is tared only there
        self._field_watch = FieldOnToolWatch()
        self.meter = ToolMeter(runtime.plant)
        torque_limits = np.minimum(-runtime.robot.tau_lower_nm, runtime.robot.tau_upper_nm)
        self.supervisor = Supervisor(runtime.plant, torque_limits, 1.0 / runtime.rates.servo_hz)
        self.supervisor.watch_joint_speeds(runtime.robot.description.joint_speed_limits_rad_s)
        self.walker = PlanWalker(self)  # decides IF, WHILE, TRY; keeps how the last statement ended

    # ------------------------------------------------------------------ plan

    def run(self, plan: Plan) -> None:
        """Run every step of ``plan``; raise TaskFailure on the first failed statement."""
        self._source, self._tool = plan.source, plan.tool
        self.walker.walk(plan.steps)  # it decides IF, WHILE and TRY; runs statements here
        if self._stopped_at is not None and self.recorder is not None:
            # Ended on its UNTIL: hold until the sample that fired it is logged (a state period at most).
            self.hold(1.0 / self.runtime.rates.state_hz)
            self._stopped_at = None
        # The plan's end (a REPL waits): all of it to the OS; else every 0.24 s simulated (runlog.writer).
        if self.log is not None:
            self.log.flush()

    def run_statement(self, segments: list[Segment]) -> bool:
        """Run a statement's segments; an UNTIL that holds ends the statement with success (True)."""
        statement_start = (self.runtime.time_s, self.meter.position.copy())
        self._event("start", segments[0], "")
        if read := self.free_air.tare_before(segments[0], self.runtime):  # a drifted wrist sensor
            self._event("warning", segments[0], read)
        for segment in segments:
            outcome = self.run_segment(segment, *statement_start)
            if moved := self._field_watch.close():  # the field on the tool's link pushed it aside
                self._event("field_on_tool", segment, moved)
            if outcome.verdict is Verdict.FAILED:
                self._fail(segment, outcome)
            if outcome.verdict is Verdict.STOPPED:
                self._stopped_at = self.runtime.time_s
                if (impact := brake_after_until(self.runtime, segment, outcome.reason)) is not None:
                    self._fail(segment, impact)  # braked through an impact over its limit
                self._event("stopped", segment, outcome.reason)
                break
            if segment.kind is SegmentKind.CONTACT_APPROACH and outcome.touched:
                self._event("contact", segment, outcome.reason)
        else:
            self._event("done", segments[-1], outcome.reason)
        self.free_air.after(segments[-1], outcome.verdict, self.meter.position - statement_start[1])
        return outcome.verdict is Verdict.STOPPED

    # ------------------------------------------- what the plan walker asks

    def senses(self) -> Senses:
        """The wrist's force and moment (world) and the measured tool point, now."""
        wrench = self.runtime.wrench
        return Senses(wrench[:3].copy(), wrench[3:].copy(), self.meter.position.copy(), self.hand.grip_n())

    def note(self, kind: str, step: Step, reason: str) -> None:
        """Write an event about ``step`` to the log."""
        self.free_air.now &= kind == "decision"  # a GRASP may leave its object on the table
        if kind == "start" and self.recorder is not None:  # a GRASP's samples are its own
            self.recorder.start_segment(self.recorder.segment, step.line)
        self._event(kind, step, reason)

    def fail(self, step: Step, reason: str) -> NoReturn:
        """Log the failure of a decided step, hold the arm, raise :class:`TaskFailure`."""
        self._event("failed", step, reason)
        self.hold(HOLD_AFTER_FAILURE_S)
        if self.log is not None:
            self.log.flush()
        raise TaskFailure(
            failure_text(step.statement, reason, self.walker.context_of(step)), step.span, self._source
        )

    def recoverable(self, failure: TaskFailure) -> bool:
        """A TRY takes over any failure but an interruption from outside."""
        return not isinstance(failure, Interrupted)

    def scene_step(self, step: AddObstacle | RemoveObstacle) -> None:
        """Add or remove an obstacle."""
        if self.obstacles is None:
            raise TaskFailure("this workcell has no room for obstacles", step.span, self._source)
        self._event("start", step, "")
        try:
            self.obstacles.apply(step)
        except TaskFailure as failure:
            self._event("failed", step, failure.message)
            self.hold(HOLD_AFTER_FAILURE_S)
            raise TaskFailure(
                failure.message + origin(self.walker.context_of(step)), step.span, self._source
            ) from None
        self._event("done", step, "")
        self.supervisor.obstacle_names = self.obstacles.scene.body_names()

    # --------------------------------------------------------------- segment

    def run_segment(
        self, segment: Segment, statement_start_s: float, statement_start_position: np.ndarray
    ) -> Outcome:
        """Run one segment until it is done, stopped or failed."""
        rt = self.runtime
        rt.reset_clocks()  # a fresh evaluation at the measured state
        ev = rt.evaluation
        start_s = rt.time_s
        meter = self.meter
        start_position, start_rotation = meter.position.copy(), meter.rotation.copy()
        goals = segment_goals(segment, start_position, start_rotation, rt.setpoint, start_s)  # and springs'
        if segment.orientation_free:  # the orientation is the null space's (seed section 4)
            goals = [(position, start_rotation.copy()) for position, _ in goals]
        robot = rt.robot
        home = home_q(robot.description) if segment.posture is not None else np.empty(0)  # this arm's
        posture, problem = posture_joints(segment.posture, home, robot.q_lower_rad, robot.q_upper_rad)
        if problem:
            return Outcome(Verdict.FAILED, problem)
        if isinstance(segment.completion, GoalReached) and not any(segment.stiffness):  # not a spring's
            if (beyond := out_of_reach(*goals[-1], rt.robot.description)) is not None:
                return Outcome(Verdict.FAILED, f"cannot reach its goal: {beyond}")
        if segment.duration_s is not None:
            error = goal_error(start_position, start_rotation, *goals[-1])
            infeasible = timed_move_problem(
                error.distance_m, error.angle_rad, segment.duration_s, rt.robot.description.capability
            )
            if infeasible is not None:
                return Outcome(Verdict.FAILED, infeasible)
        goal_index = 0
        obstacles = self.obstacles if self.obstacles is not None and self.obstacles.active else None
        # Among obstacles a goal motion gives way to their field: no reference tracked (resolve).
        among = obstacles is not None
        setpoint = setpoint_for(segment, *goals[0], ev, rt.wrench, start_s, posture, among)
        setpoint = with_landing(setpoint, segment, rt, start_rotation, self._tool)  # on steel
        search = search_phase(segment, start_s, start_position, start_rotation, rt, posture)
        if search is not None:
            setpoint = search.setpoint(setpoint)
        rt.set_setpoint(setpoint)
        self._log_segment(segment, setpoint)
        trajectory = setpoint.trajectory
        timed_until = None if trajectory is None or search else start_s + trajectory.duration_s

        def cause() -> str:
            return stall_cause(
                rt.q, robot.q_lower_rad, robot.q_upper_rad, rt.evaluation.jacobian,
                float(np.linalg.norm(rt.wrench[:3])), *goals[-1], robot.description,
                obstacles.field.influences if obstacles is not None else (),
                None if rt.rotation_plan is None else rt.rotation_plan.blocked_by,
            )  # fmt: skip

        monitor = SegmentMonitor(
            segment, start_s, start_position, statement_start_s, statement_start_position, timed_until,
            goals[-1], cause, rt.robot.tool.mass_kg,
        )  # fmt: skip
        monitor.turn_long_way = rt.rotation_plan is not None and rt.rotation_plan.long_way
        supervisor = self.supervisor
        monitor.tool_touched = supervisor.tool_touched
        supervisor.free_force_limit_n = free_limit_n(segment)
        supervisor.start(segment, start_position, goals[0][0])
        via_radius = segment.via_radius_m or 0.01
        ticks = 0
        watch_minima = obstacles is not None and isinstance(segment.completion, GoalReached)
        if self.obstacles is not None:
            self.obstacles.start_goal()
        supervisor.field_acting = False
        # Looked up once: the loop below runs every servo tick. The arrays are live views,
        # rewritten in place by the servo and the physics.
        tick, judge, idle_until = rt.tick, monitor.judge, monitor.idle_until_s
        wrench, torque, position, grip = rt.wrench, rt.servo.torque, meter.position, self.hand.grip_n
        check = supervisor.checker(wrench, torque, position)  # check(now): these views, listed once
        snapshot = Snapshot(start_s, position, meter.rotation, rt.servo.last_velocity, wrench, grip)
        # A goal motion's judge alone: its compiled gate first, the judge on the ticks it lets through.
        gate = monitor.gate if monitor.gate is not None and monitor.gate.list(snapshot) else None
        passes, gate_table = (gate.listed, gate.table) if gate is not None else (bool, None)
        gated, judge = gate is not None, monitor.judged if gate is not None else judge
        last_goal = len(goals) - 1
        every_tick = last_goal > 0 or search is not None  # VIA legs, a SEARCH: the rarer looks at every tick
        progress, progress_every, servo = self.progress, self.progress_every, rt.servo
        self._field_watch = watch = FieldOnToolWatch(supervisor.deviation_kept)  # the ticks keep the largest
        goal_points = [tuple(goal[0].tolist()) for goal in goals]  # as floats: distances every tick
        via = ViaProgress(goal_points, monitor.stall_cause)  # a VIA leg that stops getting closer fails
        minimum_at = MINIMUM_CHECK_EVERY if watch_minima and not last_goal else -1  # (from 1): the last leg's
        looks = None if obstacles is None else ObstacleTicks(obstacles, servo, supervisor, watch, position)
        move, look_at = (None, 0) if looks is None else (looks.move, looks.first_look)
        on_the_way = every_tick  # else from the look for collisions before a minimum's tick to that tick
        seen = None  # the evaluation of the last look at the field: looked at again when new (or a setpoint)
        try:
            while True:
                if move is not None:  # obstacles MOVING
                    move()
                now = tick()
                ticks += 1
                if looks is not None:
                    if ticks == look_at:
                        look_at += COLLISION_CHECK_EVERY
                        on_the_way = every_tick or 0 < minimum_at <= look_at
                        for reason in looks.collisions(ticks):
                            self._event("collision", segment, reason)
                    if rt.evaluation is not seen:  # a new field, influences, share: looked at once
                        seen = rt.evaluation
                        if reason := looks.field():
                            self._event("field_on_tool", segment, reason)
                if self.stop_requested:
                    self.stop_requested = False
                    self.hold()
                    self._event("interrupted", segment, "stopped from outside (Ctrl-C or SIGTERM)")
                    raise Interrupted(
                        f"{statement_head(segment.statement)} interrupted", segment.span, self._source
                    )
                stop = check(now)
                if stop is not None:
                    if stop.kind is StopKind.PATH:  # off its line: say if a singularity is why
                        singular = singularity(rt.q, rt.evaluation.jacobian, rt.robot.description)
                        if singular is not None:
                            stop = replace(stop, message=f"{stop.message}; {singular}")
                    return Outcome(Verdict.FAILED, stop.message, stop)
                snapshot.t_s = now
                if on_the_way:  # VIA legs, local minima among obstacles, a SEARCH
                    if goal_index < last_goal:
                        if distance_to_point(position, goal_points[goal_index]) < via_radius:
                            goal_index += 1
                            seen = None  # the null space's share changes with the setpoint
                            if goal_index == last_goal and watch_minima:
                                minimum_at = ticks + MINIMUM_CHECK_EVERY
                            supervisor.leg(goals[goal_index - 1][0], goals[goal_index][0])
                            rt.set_setpoint(
                                setpoint_for(
                                    segment,
                                    *goals[goal_index],
                                    rt.evaluation,
                                    rt.wrench,
                                    now,
                                    posture,
                                    among,
                                    True,
                                )
                            )
                        outcome = monitor.check(snapshot, completion=False) or via.stalled(
                            now, position, goal_index
                        )
                        if outcome is not None:
                            return outcome
                        continue
                    if ticks == minimum_at and obstacles is not None:
                        minimum_at += MINIMUM_CHECK_EVERY
                        on_the_way = every_tick
                        stuck = obstacles.local_minimum(position, goal_points[-1], MINIMUM_CHECK_EVERY)
                        if stuck is not None:
                            head = statement_head(segment.statement)
                            return Outcome(Verdict.FAILED, stuck.message(head).removeprefix(head).strip())
                    if search is not None:  # INSERT ... SEARCH: the pattern, then the found part led in
                        found = search.check(now, position, meter.rotation)
                        if isinstance(found, Outcome):
                            return found
                        if found is not None:  # the lateral axes return to the INSERT's compliance
                            self._event("found", segment, found)
                        monitor.searching, search = search.pattern, search.going_on
                        seen = None  # it may have set a setpoint
                if now >= idle_until and not (gated and passes(gate_table)) and (outcome := judge(snapshot)):
                    return outcome
                if progress is not None and ticks % progress_every == 0:
                    progress(Progress(segment.line, segment.statement, now))
        finally:  # the ticks since the world's last look (none falls due in them)
            if looks is not None:
                looks.close(ticks)

    def hold(self, duration_s: float = 0.0) -> None:
        """Hold the measured pose with every axis under position control (no force)."""
        hold_pose(self.runtime, duration_s)

    def _fail(self, segment: Segment, outcome: Outcome) -> None:
        reason = outcome.reason
        if outcome.stop is not None:
            if outcome.stop.collision:
                self._event("collision", segment, outcome.stop.collision)
            self._event("protective_stop", segment, reason)
        self._event("failed", segment, reason)
        self.hold(HOLD_AFTER_FAILURE_S)
        if self.log is not None:
            self.log.flush()
        text = failure_text(segment.statement, reason, self.walker.context_of(segment))
        raise TaskFailure(text, segment.span, self._source)

    # ------------------------------------------------------------------- log

    def _event(self, kind: str, segment: Step | None, reason: str) -> None:
        context = self.walker.context_of(segment) if segment is not None else ""
        if self.on_event is not None and segment is not None:
            self.on_event(kind, segment, reason, context)
        if self.log is None:
            return
        line, statement = (segment.line, segment.statement) if segment is not None else (0, "")
        self.log.event(
            self.runtime.time_s, kind, line=line, statement=statement, reason=reason, context=context
        )

    def _log_segment(self, segment: Segment, setpoint: ServoSetpoint) -> None:
        index = self.segment_count
        self.segment_count += 1
        if self.recorder is not None:
            self.recorder.start_segment(index, segment.line, self._stopped_at)
        self._stopped_at = None
        if self.log is not None:
            log_segment(self.log, self.runtime.time_s, index, segment, setpoint, self.runtime.evaluation)
