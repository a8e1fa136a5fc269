"""CONTACT to segments: approach a surface along one direction, then hold a force against it."""

from __future__ import annotations

from cosmos import plan
from cosmos.lang import ast
from cosmos.lang.compile.motion.axes import NO_FORCES, NO_FREE
from cosmos.lang.compile.motion.axis_rules import AxisRules
from cosmos.lang.compile.motion.base import ContactChange
from cosmos.lang.compile.motion.clause_values import ClauseValues
from cosmos.lang.compile.motion.clauses import clauses_of
from cosmos.lang.compile.state import HeldContact
from cosmos.rotations import readonly, signed_column

_CONTACT_APPROACH = plan.SegmentKind.CONTACT_APPROACH
_CONTACT_HOLD = plan.SegmentKind.CONTACT_HOLD


class Contact(AxisRules, ClauseValues):
    """The motion builder's CONTACT."""

    __slots__ = ()

    def contact(self, statement: ast.Contact) -> ContactChange:
        """CONTACT: the approach segment, then the hold; the contact is held after it."""
        clauses = clauses_of(statement.clauses)
        frame, _, fixture = self._frame(clauses, "CONTACT", allow_duration=False)
        axis, sign = self._translation(statement.direction, "CONTACT")
        direction_world, direction = signed_column(frame.rotation, axis, sign)
        force = self._force(clauses)
        speed = self._speed(clauses, self.defaults.contact_speed_mps)
        self._warn_impact(speed, clauses, "CONTACT")
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
            self._axes(NO_FORCES, NO_FREE),
            target=plan.RelativeTarget(readonly(tuple([d * travel for d in direction]))),
            speed=speed,
            completion=plan.ContactTouch(
                direction_world, min(self.defaults.touch_threshold_n, 0.5 * force), travel, force
            ),
            until=until,
            timeout=timeout,
        )
        self._add(
            _CONTACT_HOLD,
            statement,
            frame,
            self._axes({axis: sign * force}, NO_FREE),
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
