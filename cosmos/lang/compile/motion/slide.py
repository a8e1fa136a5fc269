"""SLIDE to a segment: move across the surface of the held contact, keeping its force."""

from __future__ import annotations

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.compile.motion.axes import AXIS_NAMES, NO_FREE, held_since
from cosmos.lang.compile.motion.axis_rules import AxisRules
from cosmos.lang.compile.motion.clause_values import ClauseValues
from cosmos.lang.compile.motion.clauses import clauses_of
from cosmos.rotations import readonly, signed_column

_SLIDE = plan.SegmentKind.SLIDE

MEASURED_SLIDE_SPEED_MPS = 0.05
"""The fastest SLIDE measured to hold its push [m/s]: the slide grid (``python
tests/run/slide_grid.py``: FORCE 5, 12 and 30 N at 5, 20 and 50 mm/s, world and a task frame
turned 45 deg) keeps the push over half its setpoint in 54 of 54 cases. Faster is not measured to
hold: FORCE 2 N at 200 mm/s on the table swung 0-10.5 N and stayed under 0.5 N for 172 ms."""


class Slide(AxisRules, ClauseValues):
    """The motion builder's SLIDE (it keeps the held contact)."""

    __slots__ = ()

    def slide(self, statement: ast.Slide) -> None:  # keeps the contact: no change
        """SLIDE: one segment across the surface of the held contact."""
        clauses = clauses_of(statement.clauses)
        contact = self._held_contact("SLIDE", statement.span)
        frame, _, _ = self._frame(clauses, "SLIDE", allow_duration=False)
        axis, sign = self._translation(statement.direction, "SLIDE")
        contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
        if axis == contact_axis:
            raise ProgramError(
                f"SLIDE {statement.direction.text} moves along the contact's own axis "
                f"({AXIS_NAMES[axis]}, CONTACT at line {contact.span.line}); slide across the "
                "surface, or MOVE to leave it",
                statement.direction.span,
            )
        self._motion_allowed(axis, lambda: f"SLIDE {statement.direction.text}", statement.direction.span)
        self._no_compliance(contact_axis, lambda: held_since(contact), statement.span)
        by = clauses.exprs.get(ast.ClauseKind.BY)
        assert by is not None  # the checker requires BY
        distance = self._positive_scalar(by, units.LENGTH, "BY")
        force = self._force(clauses) if ast.ClauseKind.FORCE in clauses.exprs else contact.force_n
        speed = self._speed(clauses, self.state.default_speed_mps)
        if speed > MEASURED_SLIDE_SPEED_MPS:
            given = ast.ClauseKind.SPEED in clauses.exprs
            self.warn(
                f"SLIDE at {speed * 1e3:g} mm/s{'' if given else ' (the SPEED in force)'} is faster than "
                f"its push was measured to hold (up to {MEASURED_SLIDE_SPEED_MPS * 1e3:g} mm/s; a 2 N "
                "push at 200 mm/s fell under 0.5 N for 172 ms): give it SPEED 50 mm/s or less",
                clauses.span_of(ast.ClauseKind.SPEED) if given else statement.span,
            )
        timeout = self._timeout(clauses)
        if timeout is not None:
            self._warn_timeout(timeout, distance, speed, None, clauses)
        offset = tuple([c * distance for c in signed_column(frame.rotation, axis, sign)[1]])
        self._add(
            _SLIDE,
            statement,
            frame,
            self._axes({contact_axis: contact_sign * force}, NO_FREE),
            target=plan.RelativeTarget(readonly(offset)),
            speed=speed,
            completion=self._goal_reached,
            until=None if clauses.until is None else self._until(clauses, frame, force_expected=True),
            timeout=timeout,
        )
