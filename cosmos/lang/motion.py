"""Motion statements (MOVE, CONTACT, SLIDE, INSERT, WAIT) to segments.

Each statement picks its task frame (``IN frame``, else the world; WAIT uses the
held contact's frame) and fills in, per task axis, the diagonal of the seed's
selection matrix Omega (motion) and its complement (force), the force setpoint,
stiffness and damping, from three sources:

- COMPLY in force: zero stiffness = force control at 0 N, else a spring;
- the held contact: its axis stays force-controlled at its force;
- the statement: CONTACT's and INSERT's force axis, INSERT's compliant axes.

The axis rule (docs/language.md, "One job per axis"): an axis that carries a
commanded force (the contact's, INSERT's) may not also be under COMPLY, and the
direction a statement moves along (SLIDE, the CONTACT approach) may be neither
force-controlled nor compliant at zero stiffness. Breaking it is an error.

:class:`MotionBuilder` is put together from the modules that hold its parts:
:mod:`~cosmos.lang.motion_move_contact` and :mod:`~cosmos.lang.motion_slide_insert_wait`
(the statements), :mod:`~cosmos.lang.motion_axes` (axis setups and the axis rule),
:mod:`~cosmos.lang.motion_clause_values` (clause values and warnings),
:mod:`~cosmos.lang.motion_clauses` (clauses by keyword, shared completions) and
:mod:`~cosmos.lang.motion_builder_base` (its attributes and the segment writer).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

from cosmos import plan
from cosmos.lang import ast
from cosmos.lang.motion_move_contact import MoveAndContact, _ContactChange
from cosmos.lang.motion_slide_insert_wait import SlideInsertWait
from cosmos.lang.state import CompileState


class MotionBuilder(MoveAndContact, SlideInsertWait):
    """Builds the segments of motion statements, one statement per :meth:`build`.

    One builder serves a whole compilation pass: ``build`` points it at each
    statement's state in turn.

    Args:
        defaults: Values used where the program gives none.
        evaluator: Evaluates expressions against the names of the statement's state.
        text_of: Source text of a span.
        warn: Records a warning.
    """

    __slots__ = ()

    def build(
        self,
        statement: ast.Move | ast.Contact | ast.Slide | ast.Insert | ast.Wait,
        state: CompileState,
        context: str,
    ) -> tuple[list[plan.Segment], CompileState]:
        """The statement's segments and the state after it.

        Args:
            statement: The motion statement.
            state: The compile state before it (the evaluator reads its names).
            context: Where an expanded statement came from (see ``Segment.context``).

        Raises:
            ProgramError: A unit, value or axis error, pointing at its cause.
        """
        self.state = state
        self.context = context
        segments: list[plan.Segment] = []
        self._segments = segments
        change: _ContactChange | None = _BUILDERS[type(statement)](self, statement)
        state = replace(
            state,
            statement_count=state.statement_count + 1,
            segment_count=state.segment_count + len(segments),
        )
        if change is not None:
            contact, released_by = change
            state = replace(state, contact=contact, contact_released_by=released_by)
        return segments, state


_BUILDERS: dict[type, Callable[[MotionBuilder, Any], _ContactChange | None]] = {
    ast.Move: MotionBuilder._move,
    ast.Contact: MotionBuilder._contact,
    ast.Slide: MotionBuilder._slide,
    ast.Insert: MotionBuilder._insert,
    ast.Wait: MotionBuilder._wait,
}
"""The builder of each motion statement type; those that change the held contact say how."""
