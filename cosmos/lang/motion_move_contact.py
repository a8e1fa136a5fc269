"""MOVE and CONTACT to segments: the motion statements that change the held contact.

MOVE releases a held contact (it leaves the surface); CONTACT approaches a
surface along one direction, then holds a force against it.
"""

from __future__ import annotations

import numpy as np

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.motion_axes import _ALL_MOTION, _NO_FORCES, _NO_FREE, AxisRules, _axis_list
from cosmos.lang.motion_clause_values import _IN_WORLD, ClauseValues
from cosmos.lang.motion_clauses import _IN, _SPEED, _clauses_of
from cosmos.lang.rotations import IDENTITY, readonly, signed_column
from cosmos.lang.state import HeldContact

_MOVE_TO = ast.MoveMode.TO
_MOVE = plan.SegmentKind.MOVE
_CONTACT_APPROACH = plan.SegmentKind.CONTACT_APPROACH
_CONTACT_HOLD = plan.SegmentKind.CONTACT_HOLD


_ContactChange = tuple[HeldContact | None, Span | None]
"""What MOVE and CONTACT change in the state: the held contact, and what released the last.

A plain tuple: a NamedTuple is made by a Python-level ``__new__``, once per statement.
"""


class MoveAndContact(AxisRules, ClauseValues):
    """The motion builder's MOVE and CONTACT."""

    __slots__ = ()

    def _move(self, statement: ast.Move) -> _ContactChange:
        clauses = _clauses_of(statement.clauses)
        frame, duration, _ = (
            self._frame(clauses, "MOVE", allow_duration=True) if _IN in clauses.exprs else _IN_WORLD
        )
        speed: float | None = None
        if _SPEED in clauses.exprs:
            if duration is not None:
                raise ProgramError(
                    "give MOVE a SPEED or a duration (IN 2 s), not both",
                    clauses.span_of(_SPEED),
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
        axes = self._axes(_NO_FORCES, _NO_FREE)
        floating = (
            [] if axes is _ALL_MOTION else [i for i, moved in enumerate(axes.motion.tolist()) if not moved]
        )
        if floating:
            comply = self.state.compliance[floating[0]]
            assert comply is not None
            self.warn(
                f"{_axis_list(floating)} compliant (COMPLY at line {comply.span.line}), so this "
                "MOVE does not control them; COMPLY NONE first to move on every axis",
                statement.span,
            )
        timeout = self._timeout(clauses)
        if timeout is not None:
            self._warn_timeout(timeout, distance, speed, duration, clauses)
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

    def _contact(self, statement: ast.Contact) -> _ContactChange:
        clauses = _clauses_of(statement.clauses)
        frame, _, fixture = (
            self._frame(clauses, "CONTACT", allow_duration=False) if _IN in clauses.exprs else _IN_WORLD
        )
        axis, sign = self._translation(statement.direction, "CONTACT")
        direction_world, direction = signed_column(frame.rotation, axis, sign)
        force = self._force(clauses)
        speed = self._speed(clauses, self.defaults.contact_speed_mps)
        self._no_compliance(axis, lambda: f"CONTACT {statement.direction.text}", statement.direction.span)
        self._warn_away_from_fixture(statement.direction, fixture, "CONTACT")
        timeout = self._timeout(clauses)
        until = (
            None
            if clauses.until is None
            else self._until(clauses, frame, force_expected=self.state.contact is not None)
        )
        travel = self.defaults.contact_max_travel_m
        self._add(
            _CONTACT_APPROACH,
            statement,
            frame,
            self._axes(_NO_FORCES, _NO_FREE),
            target=plan.RelativeTarget(readonly(tuple([d * travel for d in direction]))),
            speed=speed,
            completion=plan.ContactTouch(
                direction_world, min(self.defaults.touch_threshold_n, 0.5 * force), travel
            ),
            until=until,
            timeout=timeout,
        )
        self._add(
            _CONTACT_HOLD,
            statement,
            frame,
            self._axes({axis: sign * force}, _NO_FREE),
            target=None,
            speed=speed,
            completion=plan.ForceSettled(
                max(self.defaults.settle_tolerance_n, 0.1 * force),
                self.defaults.settle_time_s,
                self.defaults.settle_max_time_s,
            ),
            until=until,
            timeout=timeout,
        )
        contact = HeldContact(direction_world, force, frame, statement.span)
        released = statement.span if self.state.contact is not None else self.state.contact_released_by
        return contact, released
