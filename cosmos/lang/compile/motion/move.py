"""MOVE to a segment: goal-position motion to a pose or by an offset.

MOVE releases a held contact (it leaves the surface).
"""

from __future__ import annotations

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.check import limits
from cosmos.lang.compile.motion.axes import ALL_MOTION, NO_FORCES, NO_FREE, axis_list
from cosmos.lang.compile.motion.axis_rules import AxisRules
from cosmos.lang.compile.motion.base import ContactChange
from cosmos.lang.compile.motion.clause_values import ClauseValues
from cosmos.lang.compile.motion.clauses import clauses_of
from cosmos.robots import ROBOTS
from cosmos.rotations import IDENTITY, readonly

_MOVE_TO = ast.MoveMode.TO
_MOVE = plan.SegmentKind.MOVE


class Move(AxisRules, ClauseValues):
    """The motion builder's MOVE."""

    __slots__ = ()

    def move(self, statement: ast.Move) -> ContactChange:
        """MOVE TO or BY: one segment; a held contact is released."""
        clauses = clauses_of(statement.clauses)
        frame, duration, _ = self._frame(clauses, "MOVE", allow_duration=True)
        speed: float | None = None
        if ast.ClauseKind.SPEED in clauses.exprs:
            if duration is not None:
                raise ProgramError(
                    "give MOVE a SPEED or a duration (IN 2 s), not both",
                    clauses.span_of(ast.ClauseKind.SPEED),
                )
            speed = self._speed(clauses, None)
        elif duration is None:
            speed = self.state.default_speed_mps
        target: plan.Target
        distance: float | None = None
        if statement.mode is _MOVE_TO:
            goal = self.evaluator.expect_position(statement.target, "MOVE TO")
            target = plan.AbsoluteTarget(goal.position, goal.rotation)
        else:
            if isinstance(statement.target, ast.Pose):
                raise ProgramError(
                    "MOVE BY takes an offset (x, y, z); to turn the tool, MOVE TO a pose with RPY",
                    statement.target.span,
                )
            offset = self.evaluator.expect_vector3(statement.target, units.LENGTH, "MOVE BY")
            distance = float(np.linalg.norm(offset))
            if distance == 0:
                self.warn("MOVE BY (0, 0, 0) goes nowhere", statement.target.span)
            if frame.rotation is IDENTITY:  # the world's axes: the offset as it is (read-only)
                target = plan.RelativeTarget(offset)
            else:
                target = plan.RelativeTarget(readonly(frame.rotation @ offset))
        via: tuple[plan.AbsoluteTarget, ...] = ()
        if clauses.via is not None:
            via = tuple(
                plan.AbsoluteTarget(p.position, p.rotation)
                for p in (self.evaluator.expect_position(point, "VIA") for point in clauses.via.points)
            )
        axes = self._axes(NO_FORCES, NO_FREE)
        floating = (
            [] if axes is ALL_MOTION else [i for i, moved in enumerate(axes.motion.tolist()) if not moved]
        )
        if floating:
            comply = self.state.compliance[floating[0]]
            assert comply is not None
            self.warn(
                f"{axis_list(floating)} compliant (COMPLY at line {comply.span.line}), so this "
                "MOVE does not control them; COMPLY NONE first to move on every axis",
                statement.span,
            )
        timeout = self._timeout(clauses)
        if timeout is not None:
            self._warn_timeout(timeout, distance, speed, duration, clauses)
        if duration is not None and distance is not None:
            arm = ROBOTS[self.state.robot].capability
            problem = limits.timed_move_problem(distance, 0.0, duration, arm)
            if problem is not None:
                raise ProgramError(f"the arm {problem}", clauses.span_of(ast.ClauseKind.IN))
        self._add(
            _MOVE,
            statement,
            frame,
            axes,
            target=target,
            via=via,
            speed=speed,
            duration=duration,
            completion=self._goal_reached,
            until=None
            if clauses.until is None
            else self._until(
                clauses,
                frame,
                force_expected=self.state.contact is not None,
                heading_world=target.offset_world if isinstance(target, plan.RelativeTarget) else None,
            ),
            timeout=timeout,
        )
        released = statement.span if self.state.contact is not None else self.state.contact_released_by
        return None, released
