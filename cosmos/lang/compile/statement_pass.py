"""One compilation pass: statements to steps, each by the handler of its type.

:class:`StatementPass` holds what a pass over one text shares (its source, the
steps and warnings emitted, the evaluator and motion builder) and dispatches each
statement to its handler in :data:`STATEMENT_HANDLERS`, the one table from
statement type to what compiles it (each module of handlers gives its rows).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.check.statements import check_statement
from cosmos.lang.compile import blocks, branches, hand, obstacles, settings
from cosmos.lang.compile.blocks import MAX_STEPS
from cosmos.lang.compile.context import Handler, statement_text
from cosmos.lang.compile.motion import builder as motion
from cosmos.lang.compile.motion.builder import BuildStatement, MotionBuilder
from cosmos.lang.compile.state import CompileState, Defaults
from cosmos.lang.evaluate.evaluator import Evaluator
from cosmos.lang.evaluate.values import Binding, SuppressedError
from cosmos.plan.context import joined_context, origin


class StatementPass:
    """One compilation pass over the top-level statements of one text.

    Holds the source of the statement being compiled (a procedure's own text
    while it is expanded), the call and loop context, and the steps and warnings
    emitted. Its evaluator and motion builder serve every statement of the pass
    (they are pointed at each statement's state in turn, not made anew). It is
    the :class:`~cosmos.lang.compile.context.CompileContext` of the handlers.

    Args:
        defaults: Values used where the program gives none.
        fixture_names: The workcell's fixture frames, by case-folded name.
        lines_of: ``str.splitlines``, remembered for the last text.
        source: The text compiled.
    """

    __slots__ = (
        "source",
        "lines",
        "lines_of",
        "context",
        "call_stack",
        "steps",
        "warnings",
        "emitted",
        "attempts",
        "evaluator",
        "builder",
    )

    def __init__(
        self,
        defaults: Defaults,
        fixture_names: Mapping[str, Binding],
        lines_of: Callable[[str], list[str]],
        source: str,
    ):
        self.source = source
        self.lines_of = lines_of
        self.lines = lines_of(source)
        """``source.splitlines()``: ``source`` changes (to a procedure's text), so do they."""
        self.context: list[str] = []
        self.call_stack: list[str] = []
        self.steps: list[plan.Step] = []
        self.warnings: list[plan.Diagnostic] = []
        self.emitted = 0
        """Steps the top-level statement being compiled has emitted, those inside IF, WHILE, TRY too."""
        self.attempts: list[CompileState] = []
        """The state at the start of each TRY whose ON FAIL part is being compiled, innermost last."""
        self.evaluator = Evaluator(fixture_names, self.text_of)
        self.builder = MotionBuilder(defaults, self.evaluator, self.text_of, self.warn)

    def text_of(self, span: Span) -> str:
        """The source text a span covers."""
        return statement_text(span, self.lines)

    def warn(self, message: str, span: Span) -> None:
        """Record a warning, naming where the statement was expanded from."""
        if self.context:
            message += origin(joined_context(self.context))
        self.warnings.append(plan.Diagnostic(message, span))

    def emit(self, steps: Sequence[plan.Step]) -> None:
        """Append plan steps.

        Raises:
            ProgramError: The top-level statement expands to more than ``MAX_STEPS`` steps.
        """
        self.make_room(len(steps), steps[0].span)
        self.emitted += len(steps)
        self.steps.extend(steps)

    def make_room(self, steps: int, span: Span) -> None:
        """Refuse, at ``span``, ``steps`` more than the program's step limit leaves room for.

        Raises:
            ProgramError: The top-level statement would expand to more than ``MAX_STEPS`` steps.
        """
        if self.emitted + steps > MAX_STEPS:
            raise ProgramError(
                f"the program expands to more than {MAX_STEPS} steps; "
                "use fewer REPEAT passes or procedure calls",
                span,
            )

    def block(
        self, body: Sequence[ast.Statement], state: CompileState
    ) -> tuple[tuple[plan.Step, ...], CompileState]:
        """Compile a branch's statements into steps of their own (not the pass's); the state after."""
        outer = self.steps
        self.steps = []
        try:
            for inner in body:
                state = self.statement(inner, state)
            return tuple(self.steps), state
        finally:
            self.steps = outer

    def evaluator_for(self, state: CompileState) -> Evaluator:
        """The pass's evaluator, reading the names of ``state``."""
        self.evaluator.names = state.names
        return self.evaluator

    def top_level(self, statement: ast.Statement, state: CompileState) -> CompileState:
        """Check and compile one top-level statement; on an error, drop what it emitted.

        Raises:
            ProgramError: The statement is wrong (its source attached).
        """
        steps, warnings = len(self.steps), len(self.warnings)
        self.emitted = 0
        try:
            check_statement(statement)
            after = _dispatch(self, statement, state)  # at the top level there is no context to name
            return replace(after, statements=after.statements + 1)
        except ProgramError as error:
            del self.steps[steps:], self.warnings[warnings:]
            raise error.with_source(self.source) from None

    def statement(self, statement: ast.Statement, state: CompileState) -> CompileState:
        """Compile one statement (expanding blocks) and return the state after it.

        An error leaving here carries the text it points into and, for a statement
        expanded from a procedure or loop, where it was expanded from.
        """
        try:
            return _dispatch(self, statement, state)
        except ProgramError as error:
            if error.source is None:  # not yet seen by an inner statement
                if self.context and not isinstance(error, SuppressedError):
                    error.message += origin(joined_context(self.context))
                error.with_source(self.source)
            raise

    def motion(self, build: BuildStatement, statement: Any, state: CompileState) -> CompileState:
        """Compile a motion statement with the builder's method for its type."""
        self.evaluator.names = state.names
        context = joined_context(self.context)
        segments, state = self.builder.build(build, statement, state, context)
        self.emit(segments)
        return state


STATEMENT_HANDLERS: dict[type, Handler] = {
    **motion.HANDLERS,
    **settings.HANDLERS,
    **obstacles.HANDLERS,
    **hand.HANDLERS,
    **blocks.HANDLERS,
    **branches.HANDLERS,
}
"""How a statement of each type is compiled: the one table from statement type to handler,
made of the tables of the modules that hold the handlers."""


def _dispatch(run: StatementPass, statement: ast.Statement, state: CompileState) -> CompileState:
    """Compile ``statement`` by its type; an expression too deep to evaluate is the program's error."""
    try:
        return STATEMENT_HANDLERS[type(statement)](run, statement, state)
    except RecursionError:
        raise ProgramError(
            "this statement nests too deeply to compile; split its expressions", statement.span
        ) from None
