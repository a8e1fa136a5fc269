"""Checks that need only the statement itself: clauses and blocks.

The grammar lets each statement take only its own clauses, in any order; this
module adds what a grammar says badly: a clause given twice, a clause that is
required (CONTACT needs FORCE), a clause that does not fit the obstacle's shape,
blocks in the wrong place or closed with the wrong END, RETRY outside a TRY's
ON FAIL part. Checks that depend on
what came before (names, the held contact, COMPLY) are the compiler's.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from typing import Any

from cosmos.errors import ProgramError
from cosmos.lang import ast
from cosmos.lang.parse.grammar import statement_keywords

_SHAPE_CLAUSES: dict[ast.Shape, tuple[set[ast.ClauseKind], set[ast.ClauseKind]]] = {
    # shape: (required, allowed besides AT, MOVING, INFLUENCE, GAIN)
    ast.Shape.SPHERE: ({ast.ClauseKind.RADIUS}, {ast.ClauseKind.RADIUS}),
    ast.Shape.CYLINDER: (
        {ast.ClauseKind.RADIUS, ast.ClauseKind.HEIGHT},
        {ast.ClauseKind.RADIUS, ast.ClauseKind.HEIGHT},
    ),
    ast.Shape.BOX: ({ast.ClauseKind.SIZE}, {ast.ClauseKind.SIZE}),
    ast.Shape.PLANE: (set(), {ast.ClauseKind.NORMAL}),
}
_ANY_SHAPE = {ast.ClauseKind.AT, ast.ClauseKind.MOVING, ast.ClauseKind.INFLUENCE, ast.ClauseKind.GAIN}

_EXAMPLES = {
    ast.ClauseKind.FORCE: "FORCE 10 N",
    ast.ClauseKind.BY: "BY 100 mm",
    ast.ClauseKind.DEPTH: "DEPTH 25 mm",
    ast.ClauseKind.AT: "AT (0.4, 0.2, 0.5)",
    ast.ClauseKind.RADIUS: "RADIUS 50 mm",
    ast.ClauseKind.HEIGHT: "HEIGHT 0.5 m",
    ast.ClauseKind.SIZE: "SIZE (0.1, 0.2, 0.3)",
}


def clause_key(clause: ast.Clause) -> str:
    """The clause's keyword (``"SPEED"``, ``"VIA"``, ...)."""
    kind = type(clause)
    return clause.kind.value if kind is ast.ValueClause else _KEYWORDS[kind]  # type: ignore[union-attr]


def _check_clauses(keyword: str, clauses: tuple[ast.Clause, ...]) -> set[str] | dict[str, ast.Clause]:
    """The clause keywords present (a set, or a dict keyed by them); refuses a repeated one."""
    if not clauses:
        return _NONE_PRESENT
    if len(clauses) == 1:
        clause = clauses[0]
        kind = type(clause)
        return {clause.kind.value if kind is ast.ValueClause else _KEYWORDS[kind]: clause}  # type: ignore[union-attr]
    seen: dict[str, ast.Clause] = {}
    for clause in clauses:
        kind = type(clause)
        key = clause.kind.value if kind is ast.ValueClause else _KEYWORDS[kind]  # type: ignore[union-attr]
        if key in seen:
            first = seen[key].span
            hint = "; join conditions with AND or OR" if key == "UNTIL" else ""
            raise ProgramError(
                f"{key} is given twice in this {keyword} (first at line {first.line}, "
                f"column {first.column}){hint}",
                clause.span,
            )
        seen[key] = clause
    return seen


_NONE_PRESENT: set[str] = set()  # never changed
_KEYWORDS: dict[type, str] = {
    ast.ViaClause: "VIA",
    ast.UntilClause: "UNTIL",
    ast.ComplyClause: "COMPLY",
    ast.SearchClause: "SEARCH",
}
"""The keyword of each clause type other than a value clause."""


def _require(
    keyword: str, present: set[str] | dict[str, ast.Clause], needed: ast.ClauseKind, statement: ast.Statement
) -> None:
    if needed.value not in present:
        raise ProgramError(
            f"{keyword} needs {needed.value}, as in {keyword} ... {_EXAMPLES[needed]}",
            statement.span,
        )


class Place(enum.Enum):
    """Where a statement sits: what it may be."""

    TOP = "top"
    """At the top level of the program."""
    BLOCK = "block"
    """Inside a block (PROC, REPEAT, IF, WHILE, a TRY's block)."""
    HANDLER = "handler"
    """Inside a TRY's ON FAIL part (also inside an IF, WHILE or REPEAT there): RETRY may be."""


def check_statement(statement: ast.Statement, *, place: Place = Place.TOP) -> None:
    """Check one statement (and the statements of its block).

    Args:
        statement: The statement.
        place: Where it sits.

    Raises:
        ProgramError: The first problem found.
    """
    check = _CHECKS.get(type(statement))
    if check is not None:
        check(statement, place)
    elif hasattr(statement, "clauses"):  # a statement with no rule of its own: no clause twice
        _check_clauses(type(statement).__name__.upper(), statement.clauses)


def _check_move(statement: ast.Move, place: Place) -> None:
    present = _check_clauses("MOVE", statement.clauses)
    if statement.mode is ast.MoveMode.BY and "VIA" in present:
        via = next(c for c in statement.clauses if isinstance(c, ast.ViaClause))
        raise ProgramError("VIA goes with MOVE TO, not MOVE BY", via.span)


def _check_contact(statement: ast.Contact, place: Place) -> None:
    _require("CONTACT", _check_clauses("CONTACT", statement.clauses), ast.ClauseKind.FORCE, statement)


def _check_slide(statement: ast.Slide, place: Place) -> None:
    _require("SLIDE", _check_clauses("SLIDE", statement.clauses), ast.ClauseKind.BY, statement)


def _check_insert(statement: ast.Insert, place: Place) -> None:
    present = _check_clauses("INSERT", statement.clauses)
    _require("INSERT", present, ast.ClauseKind.DEPTH, statement)
    _require("INSERT", present, ast.ClauseKind.FORCE, statement)
    search = present.get("SEARCH") if isinstance(present, dict) else None
    if isinstance(search, ast.SearchClause):
        _check_search(search)


def _check_search(search: ast.SearchClause) -> None:
    """SEARCH SPIRAL (or LISSAJOUS) needs its RADIUS and its PITCH, each once."""
    keyword = f"SEARCH {search.pattern.value}"
    given = _check_clauses(keyword, search.parameters)
    for needed in (ast.ClauseKind.RADIUS, ast.ClauseKind.PITCH):
        if needed.value not in given:
            raise ProgramError(
                f"{keyword} needs {needed.value}, as in {keyword} RADIUS 6 mm PITCH 3 mm", search.span
            )


def _check_wait(statement: ast.Wait, place: Place) -> None:
    present = _check_clauses("WAIT", statement.clauses)
    if statement.duration is None and "UNTIL" not in present:
        raise ProgramError(
            "WAIT needs a duration (WAIT 2 s) or a condition (WAIT UNTIL FORCE > 5 N)",
            statement.span,
        )


def _check_comply(statement: ast.Comply, place: Place) -> None:
    if not statement.clauses:
        return
    present = _check_clauses("COMPLY", statement.clauses)
    if not statement.axes and present:
        raise ProgramError(
            "COMPLY NONE restores full stiffness and takes no STIFFNESS or DAMPING",
            statement.clauses[0].span,
        )


def _check_proc(statement: ast.ProcDef, place: Place) -> None:
    if place is not Place.TOP:
        raise ProgramError("define PROC at the top level of the program, not inside a block", statement.span)
    if _is_keyword(statement.name):
        raise ProgramError(
            f"'{statement.name.name}' is a keyword; give the PROC another name",
            statement.name.span,
        )
    seen: dict[str, ast.Ident] = {}
    for parameter in statement.parameters:
        if _is_keyword(parameter):
            raise ProgramError(
                f"'{parameter.name}' is a keyword; give the parameter another name", parameter.span
            )
        if parameter.key in seen:
            raise ProgramError(
                f"parameter '{parameter.name}' is named twice in PROC {statement.name.name}", parameter.span
            )
        seen[parameter.key] = parameter
    _check_end("PROC", statement.end_tag, statement)
    _check_body(statement.body, Place.BLOCK)


def _is_keyword(name: ast.Ident) -> bool:
    return name.name.upper() in statement_keywords() or name.key in _BLOCK_WORDS


_BLOCK_WORDS = {"end", "else", "on"}
"""Words that close or split a block: never names of procedures or parameters."""


def _check_repeat(statement: ast.Repeat, place: Place) -> None:
    _check_end("REPEAT", statement.end_tag, statement)
    _check_body(statement.body, _inner(place))


def _inner(place: Place) -> Place:
    """Where the statements of a block sit that keeps RETRY's place (IF, WHILE, REPEAT)."""
    return Place.BLOCK if place is Place.TOP else place


def _check_body(body: tuple[ast.Statement, ...], place: Place) -> None:
    """Check a block's statements; nothing may follow a RETRY (it would never run)."""
    for index, inner in enumerate(body):
        check_statement(inner, place=place)
        if isinstance(inner, ast.Retry) and index + 1 < len(body):
            raise ProgramError(
                f"this never runs: RETRY (line {inner.span.line}) runs the TRY block again; "
                "put it last in its block",
                body[index + 1].span,
            )


def _check_if(statement: ast.IfBlock, place: Place) -> None:
    _check_clauses("IF", statement.clauses)
    _check_end("IF", statement.end_tag, statement)
    _check_body(statement.then_body, _inner(place))
    _check_body(statement.else_body, _inner(place))


def _check_while(statement: ast.WhileBlock, place: Place) -> None:
    _check_clauses("WHILE", statement.clauses)
    _check_end("WHILE", statement.end_tag, statement)
    if not statement.body:
        raise ProgramError("WHILE needs statements to repeat before its END", statement.span)
    _check_body(statement.body, _inner(place))


def _check_try(statement: ast.TryBlock, place: Place) -> None:
    _check_end("TRY", statement.end_tag, statement)
    if not statement.body:
        raise ProgramError("TRY needs statements to try before ON FAIL", statement.span)
    _check_body(statement.body, Place.BLOCK)
    _check_body(statement.handler, Place.HANDLER)


def _check_retry(statement: ast.Retry, place: Place) -> None:
    if place is not Place.HANDLER:
        raise ProgramError(
            "RETRY runs a TRY block again: it belongs in the TRY's ON FAIL part "
            "(TRY ... ON FAIL ... RETRY 2 END)",
            statement.span,
        )


def _check_end(keyword: str, tag: str | None, statement: Any) -> None:
    if tag is not None and tag != keyword:
        raise ProgramError(
            f"END {tag} closes a {keyword} (opened here); write END or END {keyword}",
            statement.span,
        )


def _check_obstacle(statement: ast.Obstacle) -> None:
    present = _check_clauses("OBSTACLE", statement.clauses)
    shape = statement.shape
    required, allowed = _SHAPE_CLAUSES[shape]
    for clause in statement.clauses:
        key = clause_key(clause)
        if isinstance(clause, ast.ValueClause) and clause.kind not in allowed | _ANY_SHAPE:
            raise ProgramError(f"{key} does not apply to a {shape.value}", clause.span)
    for needed in sorted(required | {ast.ClauseKind.AT}, key=lambda k: k.value):
        if needed.value not in present:
            raise ProgramError(
                f"a {shape.value} obstacle needs {needed.value}, as in {_EXAMPLES[needed]}",
                statement.span,
            )


_CHECKS: dict[type, Callable[[Any, Place], None]] = {
    ast.Move: _check_move,
    ast.Contact: _check_contact,
    ast.Slide: _check_slide,
    ast.Insert: _check_insert,
    ast.Wait: _check_wait,
    ast.Comply: _check_comply,
    ast.Obstacle: lambda statement, place: _check_obstacle(statement),
    ast.ProcDef: _check_proc,
    ast.Repeat: _check_repeat,
    ast.IfBlock: _check_if,
    ast.WhileBlock: _check_while,
    ast.TryBlock: _check_try,
    ast.Retry: _check_retry,
}
"""The check of each statement type that has clauses or a block (LET, FRAME, SPEED,
OBSTACLE REMOVE and CALL have neither)."""
