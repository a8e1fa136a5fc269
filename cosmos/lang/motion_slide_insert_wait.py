"""SLIDE, INSERT and WAIT to segments: the motion statements that keep the held contact.

SLIDE moves across the surface of the held contact; INSERT pushes along one
direction to a depth, compliant across it; WAIT holds still (and holds the
contact's force) for a time or until a condition.
"""

from __future__ import annotations

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.conditions import comparisons
from cosmos.lang.motion_axes import _AXIS_NAMES, _NO_FREE, AxisRules, _held_since
from cosmos.lang.motion_clause_values import _IN_WORLD, ClauseValues
from cosmos.lang.motion_clauses import _BY, _DEPTH, _FORCE, _IN, _clauses_of
from cosmos.lang.rotations import readonly, signed_column
from cosmos.lang.state import WORLD

_SLIDE = plan.SegmentKind.SLIDE
_INSERT = plan.SegmentKind.INSERT
_WAIT = plan.SegmentKind.WAIT


class SlideInsertWait(AxisRules, ClauseValues):
    """The motion builder's SLIDE, INSERT and WAIT."""

    __slots__ = ()

    def _slide(self, statement: ast.Slide) -> None:  # keeps the contact: no change
        clauses = _clauses_of(statement.clauses)
        contact = self._held_contact("SLIDE", statement.span)
        frame, _, _ = (
            self._frame(clauses, "SLIDE", allow_duration=False) if _IN in clauses.exprs else _IN_WORLD
        )
        axis, sign = self._translation(statement.direction, "SLIDE")
        contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
        if axis == contact_axis:
            raise ProgramError(
                f"SLIDE {statement.direction.text} moves along the contact's own axis "
                f"({_AXIS_NAMES[axis]}, CONTACT at line {contact.span.line}); slide across the "
                "surface, or MOVE to leave it",
                statement.direction.span,
            )
        self._motion_allowed(axis, lambda: f"SLIDE {statement.direction.text}", statement.direction.span)
        self._no_compliance(contact_axis, lambda: _held_since(contact), statement.span)
        by = clauses.exprs.get(_BY)
        assert by is not None  # the checker requires BY
        distance = self._positive_scalar(by, units.LENGTH, "BY")
        force = self._force(clauses) if _FORCE in clauses.exprs else contact.force_n
        speed = self._speed(clauses, self.state.default_speed_mps)
        timeout = self._timeout(clauses)
        if timeout is not None:
            self._warn_timeout(timeout, distance, speed, None, clauses)
        offset = tuple([c * distance for c in signed_column(frame.rotation, axis, sign)[1]])
        self._add(
            _SLIDE,
            statement,
            frame,
            self._axes({contact_axis: contact_sign * force}, _NO_FREE),
            target=plan.RelativeTarget(readonly(offset)),
            speed=speed,
            completion=self._goal_reached,
            until=None if clauses.until is None else self._until(clauses, frame, force_expected=True),
            timeout=timeout,
        )

    def _insert(self, statement: ast.Insert) -> None:
        clauses = _clauses_of(statement.clauses)
        frame, _, fixture = (
            self._frame(clauses, "INSERT", allow_duration=False) if _IN in clauses.exprs else _IN_WORLD
        )
        axis, sign = self._translation(statement.direction, "INSERT")
        direction_world = signed_column(frame.rotation, axis, sign)[0]
        depth_expr = clauses.exprs.get(_DEPTH)
        assert depth_expr is not None  # the checker requires DEPTH
        depth = self._positive_scalar(depth_expr, units.LENGTH, "DEPTH")
        force = self._force(clauses)
        contact = self.state.contact
        forces = {axis: sign * force}
        contact_axis = None
        if contact is not None:
            contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
            if contact_axis != axis:
                forces[contact_axis] = contact_sign * contact.force_n

        def what() -> str:  # for messages only: built when one is given
            return f"INSERT {statement.direction.text}"

        if clauses.comply is not None:
            free = {ref.axis._value_ for ref in clauses.comply.axes}
            for ref in clauses.comply.axes:
                if ref.axis._value_ in forces:
                    because = (
                        f"{what()} pushes along it"
                        if ref.axis._value_ == axis
                        else f"it carries {_held_since(contact)}"
                    )
                    raise ProgramError(
                        f"{ref.axis.name} cannot be compliant here: {because}; leave it out of COMPLY",
                        ref.span,
                    )
        else:
            lateral = [i for i in range(3) if i != axis]
            free = {i for i in lateral + [i + 3 for i in lateral] if i != contact_axis}
        self._no_compliance(axis, what, statement.direction.span)
        if contact_axis is not None and contact_axis != axis:
            self._no_compliance(contact_axis, lambda: _held_since(contact), statement.span)
        if contact is None:
            self.warn(
                f"no contact is held, so {what()} pushes {force:g} N into free space (at up to "
                f"{self._speed(clauses, self.defaults.insert_speed_mps) * 1000:g} mm/s) until it "
                "meets something; make a CONTACT first",
                statement.span,
            )
        self._warn_away_from_fixture(statement.direction, fixture, "INSERT")
        self._add(
            _INSERT,
            statement,
            frame,
            self._axes(forces, free),
            target=None,
            speed=self._speed(clauses, self.defaults.insert_speed_mps),
            completion=plan.DepthReached(direction_world, depth),
            until=None if clauses.until is None else self._until(clauses, frame, force_expected=True),
            timeout=self._timeout(clauses),
            jam_check=self._jam_check,
        )

    def _wait(self, statement: ast.Wait) -> None:
        clauses = _clauses_of(statement.clauses)
        duration = None
        if statement.duration is not None:
            duration = self._positive_scalar(statement.duration, units.TIME, "WAIT")
        contact = self.state.contact
        frame = WORLD if contact is None else contact.frame
        forces: dict[int, float] = {}
        if contact is not None:
            contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
            self._no_compliance(contact_axis, lambda: _held_since(contact), statement.span)
            forces[contact_axis] = contact_sign * contact.force_n
        axes = self._axes(forces, _NO_FREE)
        until = (
            None if clauses.until is None else self._until(clauses, frame, force_expected=contact is not None)
        )
        movable = not axes.all_motion or any(c is not None and c.stiffness > 0 for c in self.state.compliance)
        if until is not None and not movable:
            for comparison in comparisons(until):
                if comparison.quantity is plan.Quantity.DISTANCE:
                    raise ProgramError(
                        "WAIT holds the tool still (no contact held, nothing compliant), so "
                        "DISTANCE stays 0 and cannot be sensed here",
                        comparison.span,
                    )
        timeout = self._timeout(clauses)
        if duration is None and timeout is None:
            self.warn("WAIT UNTIL without TIMEOUT may wait for ever; add TIMEOUT", statement.span)
        self._add(
            _WAIT,
            statement,
            frame,
            axes,
            target=None,
            speed=self.defaults.contact_speed_mps if forces else None,
            completion=plan.UntilOnly() if duration is None else plan.Elapsed(duration),
            until=until,
            timeout=timeout,
        )
