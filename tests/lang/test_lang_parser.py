"""The grammar and the tree builder: layout, case, keywords as names, spans, units."""

from __future__ import annotations

import pytest

from cosmos.errors import ProgramError
from cosmos.lang import ast, needs_more_input, parse_program
from cosmos.lang.parse.builder import TreeBuilder
from cosmos.lang.parse.grammar import lark_parser
from cosmos.lang.units import KNOWN_UNITS


def statements(source: str) -> tuple[ast.Statement, ...]:
    return parse_program(source, "p.cos").statements


def test_every_grammar_rule_has_a_builder() -> None:
    # A rule reaches the builder unless it is inlined (_rule) or always has one
    # child and is marked ?rule; every other one needs a method.
    missing = set()
    for rule in lark_parser().rules:
        name = rule.alias or rule.origin.name
        if name.startswith("_") or (rule.options.expand1 and len(rule.expansion) == 1):
            continue
        if not hasattr(TreeBuilder, name):
            missing.add(name)
    assert not missing


def test_case_does_not_matter() -> None:
    upper = statements("MOVE TO HOLE + (0, 0, 10 MM) SPEED 0.1 M/S\n")
    lower = statements("move to hole + (0, 0, 10 mm) speed 0.1 m/s\n")
    assert type(upper[0]) is type(lower[0]) is ast.Move
    assert upper[0].clauses[0].kind is lower[0].clauses[0].kind is ast.ClauseKind.SPEED  # type: ignore[union-attr]


def test_keywords_double_as_names_where_no_keyword_fits() -> None:
    let, speed, move = statements("LET speed = 0.2 m/s\nSPEED speed\nMOVE BY (x, 0, 0) SPEED speed")
    assert isinstance(let, ast.Let) and let.name.name == "speed"
    assert isinstance(speed, ast.SetSpeed) and speed.value == ast.Name("speed", speed.value.span)
    assert isinstance(move, ast.Move)
    assert isinstance(move.target, ast.Vector) and isinstance(move.target.items[0], ast.Name)


def test_keywords_end_at_word_boundaries() -> None:
    [let] = statements("LET speedy = 3")
    assert isinstance(let, ast.Let) and let.name.name == "speedy"
    with pytest.raises(ProgramError, match="did you mean SPEED"):
        statements("MOVE TO hole SPEEDY 3")


def test_layout_comments_semicolons_and_continuations() -> None:
    source = "# a comment\nWAIT 1 s ; WAIT 2 s  # trailing\n\nMOVE TO hole \\\n  SPEED 0.1 m/s\n"
    first, second, move = statements(source)
    assert isinstance(first, ast.Wait) and isinstance(second, ast.Wait)
    assert isinstance(move, ast.Move) and len(move.clauses) == 1
    assert (move.span.line, move.span.end_line) == (4, 5)


def test_spans_cover_the_statement_and_its_values() -> None:
    [contact] = statements("  CONTACT DOWN FORCE 10 N TIMEOUT 5 s")
    assert isinstance(contact, ast.Contact)
    assert (contact.span.line, contact.span.column, contact.span.end_column) == (1, 3, 38)
    force = contact.clauses[0]
    assert isinstance(force, ast.ValueClause)
    assert (force.span.column, force.value.span.column, force.value.span.end_column) == (16, 22, 26)
    assert contact.direction.span.column == 11


def test_directions() -> None:
    source = "\n".join(f"CONTACT {d} FORCE 1 N" for d in ("UP", "DOWN", "-X", "+Y", "Z"))
    found = [(s.direction.axis, s.direction.sign) for s in statements(source)]  # type: ignore[union-attr]
    assert found == [(ast.Axis.Z, 1), (ast.Axis.Z, -1), (ast.Axis.X, -1), (ast.Axis.Y, 1), (ast.Axis.Z, 1)]


def test_blocks() -> None:
    proc, repeat, call, bare = statements(
        "PROC pick\n  WAIT 1 s\nEND PROC\nREPEAT 2 TIMES\n  pick\nEND\nCALL pick\npick"
    )
    assert isinstance(proc, ast.ProcDef) and proc.end_tag == "PROC" and len(proc.body) == 1
    assert (proc.span.line, proc.span.end_column) == (1, 10)
    assert isinstance(repeat, ast.Repeat) and repeat.end_tag is None
    assert isinstance(repeat.body[0], ast.Call)
    assert isinstance(call, ast.Call) and isinstance(bare, ast.Call)


@pytest.mark.parametrize("unit", KNOWN_UNITS)
def test_every_documented_unit_joins_its_number(unit: str) -> None:
    [let] = statements(f"LET q = 12 {unit}")
    assert isinstance(let, ast.Let)
    assert let.value == ast.Number(12.0, unit, let.value.span)


def test_a_word_after_a_number_that_is_not_a_unit_is_an_error() -> None:
    with pytest.raises(ProgramError, match="'parsecs' is not a unit"):
        statements("LET q = 12 parsecs")


def test_needs_more_input_inside_an_open_block() -> None:
    assert needs_more_input("PROC pick\n  WAIT 1 s\n")
    assert needs_more_input("REPEAT 3\n")
    assert not needs_more_input("PROC pick\n  WAIT 1 s\nEND\n")
    assert not needs_more_input("MOVE (1, 2, 3)\n")
    assert not needs_more_input("WAIT 1 s")


@pytest.mark.parametrize(
    ("text", "column"),
    [
        ("LET x = " + "(" * 65 + "1" + ")" * 65, 9 + 64),
        ("LET x = " + "(1) + " * 70 + "(" * 65 + "1" + ")" * 65, 9 + 6 * 70 + 64),
        ("LET x = (((1)\n" + "LET y = (" * 63 + "\n", 9 + 9 * 62),  # unclosed ones add up across lines
    ],
)
def test_parentheses_nested_too_deep_are_refused_where_the_limit_is_passed(text: str, column: int) -> None:
    with pytest.raises(ProgramError, match="nested more than 64 deep") as raised:
        parse_program(text, "f.cos")
    assert raised.value.span is not None and raised.value.span.column == column


def test_parentheses_nested_to_the_limit_are_accepted() -> None:
    deep = "LET x = " + "(" * 64 + "1" + ")" * 64 + "  # ((((((\n"
    parse_program(deep * 3 + "LET y = " + "(1) + " * 200 + "1\n", "f.cos")
