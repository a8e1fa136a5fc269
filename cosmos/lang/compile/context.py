"""What a statement handler sees of the compilation pass it runs in.

The handlers (``settings``, ``obstacles``, ``blocks``, and the motion builder
through the pass) are written against :class:`CompileContext`, which
:class:`~cosmos.lang.compile.statement_pass.StatementPass` implements; so no
handler imports the pass that calls it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Protocol

from cosmos import plan
from cosmos.errors import Span
from cosmos.lang import ast
from cosmos.lang.compile.state import CompileState
from cosmos.lang.evaluate.evaluator import Evaluator


class CompileContext(Protocol):
    """One compilation pass, as its statement handlers use it.

    Attributes:
        source: The text of the statement being compiled (a procedure's own
            text while it is expanded).
        lines: ``source.splitlines()``.
        context: Where the statement was expanded from, outermost first
            (``"PROC p called at line 3"``, ``"REPEAT pass 1 of 2 at line 5"``).
        call_stack: Case-folded names of the procedures being expanded.
        attempts: The state at the start of each TRY whose ON FAIL part is
            being compiled, innermost last (what a RETRY runs again from).
    """

    source: str
    lines: list[str]
    context: list[str]
    call_stack: list[str]
    attempts: list[CompileState]

    def text_of(self, span: Span) -> str:
        """The source text a span covers."""
        ...

    def lines_of(self, source: str) -> list[str]:
        """``source.splitlines()`` (remembered for the last text)."""
        ...

    def warn(self, message: str, span: Span) -> None:
        """Record a warning (naming where the statement was expanded from)."""
        ...

    def emit(self, steps: Sequence[plan.Step]) -> None:
        """Append plan steps (refused past the program's step limit)."""
        ...

    def make_room(self, steps: int, span: Span) -> None:
        """Refuse, at ``span``, ``steps`` more than the program's step limit leaves room for."""
        ...

    def evaluator_for(self, state: CompileState) -> Evaluator:
        """The pass's evaluator, reading the names of ``state``."""
        ...

    def statement(self, statement: ast.Statement, state: CompileState) -> CompileState:
        """Compile one statement of a block's body; the state after it."""
        ...

    def block(
        self, body: Sequence[ast.Statement], state: CompileState
    ) -> tuple[tuple[plan.Step, ...], CompileState]:
        """Compile a branch's statements into steps of their own; the state after them."""
        ...

    def motion(self, build: Callable[[Any, Any], Any], statement: Any, state: CompileState) -> CompileState:
        """Compile a motion statement with the motion builder's method ``build`` for it."""
        ...


Handler = Callable[[CompileContext, Any, CompileState], CompileState]
"""Compiles one statement of a type: (pass, statement, state before) -> state after."""


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
