"""A motion statement's clauses sorted by keyword, and the completions its segments share.

Part of the motion builder (:mod:`cosmos.lang.compile.motion.builder`): a statement's
clauses by keyword, and the goal and jam checks one ``Defaults`` gives every
segment that needs them.
"""

from __future__ import annotations

from dataclasses import dataclass

from cosmos import plan
from cosmos.errors import Span
from cosmos.lang import ast
from cosmos.lang.compile.state import Defaults


@dataclass(slots=True)
class Clauses:
    """A statement's clauses by keyword (the checker has refused duplicates).

    ``exprs`` holds the value of each value clause by its kind (``.get``: None where absent).
    """

    given: tuple[ast.Clause, ...]
    exprs: dict[ast.ClauseKind, ast.Expr]
    via: ast.ViaClause | None
    until: ast.UntilClause | None
    comply: ast.ComplyClause | None

    def span_of(self, kind: ast.ClauseKind) -> Span:
        """The span of the value clause of ``kind`` (keyword and value), which is given."""
        return next(c.span for c in self.given if type(c) is _VALUE_CLAUSE and c.kind is kind)


def clauses_of(clauses: tuple[ast.Clause, ...]) -> Clauses:
    """A statement's clauses sorted by keyword (one shared, never changed, value for none)."""
    if not clauses:
        return _NO_CLAUSES
    exprs: dict[ast.ClauseKind, ast.Expr] = {}
    found = Clauses(clauses, exprs, None, None, None)
    for clause in clauses:
        kind = type(clause)
        if kind is _VALUE_CLAUSE:
            exprs[clause.kind] = clause.value  # type: ignore[union-attr]
        elif kind is _VIA_CLAUSE:
            found.via = clause  # type: ignore[assignment]
        elif kind is _UNTIL_CLAUSE:
            found.until = clause  # type: ignore[assignment]
        elif kind is _COMPLY_CLAUSE:
            found.comply = clause  # type: ignore[assignment]
        # INSERT's SEARCH clause is read by the INSERT handler itself
    return found


_NO_CLAUSES = Clauses((), {}, None, None, None)
"""The clauses of a statement without any (its dictionaries stay empty)."""
_VALUE_CLAUSE = ast.ValueClause
_VIA_CLAUSE = ast.ViaClause
_UNTIL_CLAUSE = ast.UntilClause
_COMPLY_CLAUSE = ast.ComplyClause


@dataclass(frozen=True, eq=False)
class Completions:
    """The immutable plan values one ``Defaults`` gives every segment that needs them."""

    goal_reached: plan.GoalReached
    jam_check: plan.JamCheck


def completions_of(defaults: Defaults) -> Completions:
    """The goal tolerances and jam check of ``defaults``."""
    return Completions(
        plan.GoalReached(
            position_tolerance_m=defaults.position_tolerance_m,
            orientation_tolerance_rad=defaults.orientation_tolerance_rad,
            speed_tolerance_mps=defaults.rest_speed_mps,
        ),
        plan.JamCheck(
            stall_speed_mps=defaults.jam_stall_speed_mps,
            stall_time_s=defaults.jam_stall_time_s,
        ),
    )
