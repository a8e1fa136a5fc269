"""WAIT to a segment: hold still (and hold the contact's force) for a time or until a condition."""

from __future__ import annotations

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.compile.motion.axes import NO_FREE, held_since
from cosmos.lang.compile.motion.axis_rules import AxisRules
from cosmos.lang.compile.motion.clause_values import ClauseValues
from cosmos.lang.compile.motion.clauses import clauses_of
from cosmos.lang.compile.motion.conditions import comparisons
from cosmos.lang.compile.state import WORLD

_WAIT = plan.SegmentKind.WAIT


class Wait(AxisRules, ClauseValues):
    """The motion builder's WAIT (it keeps the held contact)."""

    __slots__ = ()

    def wait(self, statement: ast.Wait) -> None:
        """WAIT: one segment holding still (and the contact's force)."""
        clauses = clauses_of(statement.clauses)
        duration = None
        if statement.duration is not None:
            duration = self._positive_scalar(statement.duration, units.TIME, "WAIT")
        contact = self.state.contact
        frame = WORLD if contact is None else contact.frame
        if contact is None and any(c is not None and c.stiffness > 0 for c in self.state.compliance):
            frame = self.state.last_frame  # a press on a spring goes on in the frame it was made in
        forces: dict[int, float] = {}
        if contact is not None:
            contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
            self._no_compliance(contact_axis, lambda: held_since(contact), statement.span)
            forces[contact_axis] = contact_sign * contact.force_n
        axes = self._axes(forces, NO_FREE)
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
