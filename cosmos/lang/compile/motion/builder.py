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

:class:`MotionBuilder` is put together from the modules that hold its parts: one
per statement (``move``, ``contact``, ``slide``, ``insert``, ``wait``), on
``axis_rules`` (axis setups and the axis rule), ``clause_values`` (clause values
and warnings), ``clauses`` (clauses by keyword, shared completions) and ``base``
(its attributes and the segment writer).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

from cosmos import plan
from cosmos.lang import ast
from cosmos.lang.compile.context import CompileContext, Handler
from cosmos.lang.compile.motion.base import ContactChange
from cosmos.lang.compile.motion.contact import Contact
from cosmos.lang.compile.motion.insert import Insert
from cosmos.lang.compile.motion.move import Move
from cosmos.lang.compile.motion.slide import Slide
from cosmos.lang.compile.motion.wait import Wait
from cosmos.lang.compile.state import CompileState, TaskFrame

BuildStatement = Callable[[Any, Any], ContactChange | None]
"""One of the builder's statement methods (``MotionBuilder.move``, ...): the change of
the held contact it makes, None for none."""


class MotionBuilder(Move, Contact, Slide, Insert, Wait):
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
        build_statement: BuildStatement,
        statement: ast.Move | ast.Contact | ast.Slide | ast.Insert | ast.Wait,
        state: CompileState,
        context: str,
    ) -> tuple[list[plan.Segment], CompileState]:
        """The statement's segments and the state after it.

        Args:
            build_statement: The method for the statement's type (``MotionBuilder.move``, ...).
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
        change = build_statement(self, statement)
        state = replace(
            state,
            statement_count=state.statement_count + 1,
            segment_count=state.segment_count + len(segments),
        )
        if segments:
            last = segments[-1]
            state = replace(state, last_frame=TaskFrame(last.frame_name, last.frame_rotation))
        if change is not None:
            contact, released_by = change
            state = replace(state, contact=contact, contact_released_by=released_by)
        return segments, state


def _handler(build: BuildStatement) -> Handler:
    """The compiler's handler of a motion statement: the builder's method for it, in the pass."""

    def handler(run: CompileContext, statement: Any, state: CompileState) -> CompileState:
        return run.motion(build, statement, state)

    return handler


HANDLERS: dict[type, Handler] = {
    ast.Move: _handler(MotionBuilder.move),
    ast.Contact: _handler(MotionBuilder.contact),
    ast.Slide: _handler(MotionBuilder.slide),
    ast.Insert: _handler(MotionBuilder.insert),
    ast.Wait: _handler(MotionBuilder.wait),
}
"""The handler of each motion statement type (merged into the compiler's one table)."""
