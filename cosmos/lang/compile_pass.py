"""One compilation pass: statements to steps, each by the handler of its type.

:class:`_Run` holds what a pass over one text shares (its source, the steps and
warnings emitted, the evaluator and motion builder) and dispatches each statement
to its handler (:data:`_DISPATCH`): motion statements to the
:class:`~cosmos.lang.motion.MotionBuilder`, the others to the functions of
:mod:`~cosmos.lang.compile_settings`, :mod:`~cosmos.lang.compile_obstacles` and
:mod:`~cosmos.lang.compile_blocks`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from cosmos import plan
from cosmos.errors import ProgramError, Span
from cosmos.lang import ast
from cosmos.lang.checker import check_statement
from cosmos.lang.compile_blocks import MAX_STEPS, expand_call, expand_repeat, register_procedure
from cosmos.lang.compile_obstacles import compile_obstacle, compile_remove_obstacle
from cosmos.lang.compile_settings import compile_comply, compile_definition, compile_speed
from cosmos.lang.motion import MotionBuilder
from cosmos.lang.state import CompileState
from cosmos.lang.values import Evaluator, SuppressedError

if TYPE_CHECKING:
    from cosmos.lang.compiler import Compiler


def statement_text(span: Span, source: str | list[str]) -> str:
    """The source text a span covers, lines joined with a space.

    Args:
        span: The span.
        source: The text, or its lines (``str.splitlines``) when called often.
    """
    lines = source.splitlines() if isinstance(source, str) else source
    if not 1 <= span.line <= len(lines):
        return ""
    if span.end_line == span.line:
        return lines[span.line - 1][span.column - 1 : span.end_column - 1].strip()
    parts = [lines[span.line - 1][span.column - 1 :]]
    parts += lines[span.line : span.end_line - 1]
    if span.end_line <= len(lines):
        parts.append(lines[span.end_line - 1][: span.end_column - 1])
    return " ".join(part.strip().rstrip("\\").strip() for part in parts if part.strip())


class _Run:
    """One compilation pass over the top-level statements of one text.

    Holds the source of the statement being compiled (a procedure's own text
    while it is expanded), the call and loop context, and the steps and warnings
    emitted. Its evaluator and motion builder serve every statement of the pass
    (they are pointed at each statement's state in turn, not made anew).
    """

    __slots__ = (
        "compiler",
        "source",
        "lines",
        "context",
        "call_stack",
        "steps",
        "warnings",
        "first_step",
        "evaluator",
        "builder",
    )

    def __init__(self, compiler: Compiler, source: str):
        self.compiler = compiler
        self.source = source
        self.lines = compiler.lines_of(source)
        """``source.splitlines()``: ``source`` changes (to a procedure's text), so do they."""
        self.context: list[str] = []
        self.call_stack: list[str] = []
        self.steps: list[plan.Step] = []
        self.warnings: list[plan.Diagnostic] = []
        self.first_step = 0
        """Index in ``steps`` of the first step of the top-level statement being compiled."""
        self.evaluator = Evaluator(compiler._fixture_names, self.text_of)
        self.builder = MotionBuilder(compiler.defaults, self.evaluator, self.text_of, self.warn)

    def text_of(self, span: Span) -> str:
        lines = self.lines
        line = span.line
        if line == span.end_line and 0 < line <= len(lines):  # most statements: statement_text's first case
            return lines[line - 1][span.column - 1 : span.end_column - 1].strip()
        return statement_text(span, lines)

    def warn(self, message: str, span: Span) -> None:
        if self.context:
            message += f" (in {'; '.join(self.context)})"
        self.warnings.append(plan.Diagnostic(message, span))

    def emit(self, steps: Sequence[plan.Step]) -> None:
        if len(self.steps) - self.first_step + len(steps) > MAX_STEPS:
            raise ProgramError(
                f"the program expands to more than {MAX_STEPS} steps; use fewer REPEATs",
                steps[0].span,
            )
        self.steps.extend(steps)

    def top_level(self, statement: ast.Statement, state: CompileState) -> CompileState:
        """Check and compile one top-level statement; on an error, drop what it emitted.

        Raises:
            ProgramError: The statement is wrong (its source attached).
        """
        steps, warnings = len(self.steps), len(self.warnings)
        self.first_step = steps
        try:
            check_statement(statement)
            return _dispatch(self, statement, state)  # at the top level there is no context to name
        except ProgramError as error:
            del self.steps[steps:], self.warnings[warnings:]
            raise error.with_source(self.source) from None

    # ------------------------------------------------------------ dispatch

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
                    error.message += f" (in {'; '.join(self.context)})"
                error.with_source(self.source)
            raise

    def _evaluator(self, state: CompileState) -> Evaluator:
        """The pass's evaluator, reading the names of ``state``."""
        evaluator = self.evaluator
        evaluator.names = state.names
        return evaluator

    def _motion(self, statement: ast.Statement, state: CompileState) -> CompileState:
        self.evaluator.names = state.names
        context = "; ".join(self.context) if self.context else ""
        segments, state = self.builder.build(statement, state, context)  # type: ignore[arg-type]
        steps = self.steps
        if len(steps) - self.first_step + len(segments) > MAX_STEPS:
            self.emit(segments)  # raises
        steps.extend(segments)
        return state


def _dispatch(run: _Run, statement: ast.Statement, state: CompileState) -> CompileState:
    """Compile ``statement`` by its type (:data:`_DISPATCH`); too deep a nesting is the program's error."""
    try:
        return _DISPATCH.get(type(statement), expand_call)(run, statement, state)
    except RecursionError:
        raise ProgramError(
            "this statement nests too deeply to compile; split its expressions", statement.span
        ) from None


_DISPATCH: dict[type, Callable[[_Run, Any, CompileState], CompileState]] = {
    ast.Move: _Run._motion,
    ast.Contact: _Run._motion,
    ast.Slide: _Run._motion,
    ast.Insert: _Run._motion,
    ast.Wait: _Run._motion,
    ast.SetSpeed: compile_speed,
    ast.Comply: compile_comply,
    ast.Let: compile_definition,
    ast.FrameDef: compile_definition,
    ast.Obstacle: compile_obstacle,
    ast.RemoveObstacle: compile_remove_obstacle,
    ast.ProcDef: register_procedure,
    ast.Repeat: expand_repeat,
}
"""How a statement of each type is compiled (a CALL, the only other type, by ``expand_call``)."""
