"""The fast parser (cosmos/lang/fastparse.py) against Lark: same trees, same spans.

Lark, driven by its own lexer and parser, is the reference: for any text the
fast path either builds exactly the tree Lark builds (spans included) or gives
up, and then Lark must reject the text too (its error is what users see).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cosmos.errors import Span
from cosmos.lang import ast
from cosmos.lang.parser import _fast_parse, _raw_parse, parse_program

ROOT = Path(__file__).parents[2]
DOCS = re.findall(r"```cosmos\n(.*?)```", (ROOT / "docs" / "language.md").read_text(), re.S)
PROGRAMS = sorted((ROOT / "programs").glob("*.cos"))

LAYOUTS = [
    "",
    "\n\n",
    "WAIT 1 s",  # no final line break
    "  \tWAIT 1 s # a comment\n# only a comment",
    "WAIT 1 s\r\nWAIT 2 s\r\n",  # CRLF
    "WAIT 1 s\rWAIT 2 s\n",  # a lone CR ends a statement but not a line (as Lark counts)
    "WAIT 1 s ; WAIT 2 s;WAIT 3 s",
    "MOVE TO (0.5, \\\n   0.1, 0.3) \\\n SPEED 0.1 m/s\n",
    "move to HOLE + (0, 0, 10 MM) speed 0.1 M/S\n",
    "LET speed = 0.2 m/s\nSPEED speed\nMOVE BY (speed * 1 s, 0, 0) SPEED speed\n",
    "LET in = (1, 2, 3)\nLET x = -(in) + +(2 * in) - in * 3\n",
    "MOVE TO (1 mm, 2mm, 3 N m/rad) RPY (180 deg, 0, .5e1 deg)\n",
    "LET x = ((((1)))) + (2, (3), 4)\n",
    "WAIT UNTIL (FORCE > 1 N OR TORQUE RZ < 2 Nm) AND DISTANCE >= 3 mm TIMEOUT 5 s\n",
    "PROC p\n  WAIT 1 s\nEND PROC\nREPEAT 2 TIMES\n  p\n  CALL p\nEND\n",
    "OBSTACLE ball SPHERE AT (0.4, 0.2, 0.5) RADIUS 50 mm\nOBSTACLE REMOVE ball\n",
    "COMPLY X Y RX STIFFNESS 200 N/m DAMPING 20 N s/m\nCOMPLY NONE\n",
    "INSERT DOWN DEPTH 25 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s\n",
]


def _same_tree(text: str) -> Any:
    fast = _fast_parse(text)
    assert fast is not None, f"the fast path gave up on a valid program: {text!r}"
    assert fast == _raw_parse(text)
    return fast


@pytest.mark.parametrize("text", LAYOUTS + DOCS, ids=lambda text: repr(text[:30]))
def test_fast_path_builds_the_tree_lark_builds(text: str) -> None:
    _same_tree(text)


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda path: path.stem)
def test_fast_path_builds_the_tree_lark_builds_for_the_example_programs(path: Path) -> None:
    _same_tree(path.read_text())


def test_spans_of_nested_expressions_counted_by_hand() -> None:
    #          1        10        20        30
    #          |        |         |         |
    source = "LET v = (1, 2 mm) + x * -3\nLET w = \\\n  (4, 5)\n"
    let, other = parse_program(source, "f.cos").statements
    assert isinstance(let, ast.Let) and isinstance(other, ast.Let)
    total = let.value
    assert isinstance(total, ast.Binary) and total.op == "+"
    assert total.span == Span("f.cos", 1, 9, 1, 27)
    vector, product = total.left, total.right
    assert isinstance(vector, ast.Vector) and vector.span == Span("f.cos", 1, 9, 1, 18)
    assert vector.items[1] == ast.Number(2.0, "mm", Span("f.cos", 1, 13, 1, 17))
    assert isinstance(product, ast.Binary) and product.span == Span("f.cos", 1, 21, 1, 27)
    assert product.left == ast.Name("x", Span("f.cos", 1, 21, 1, 22))
    assert isinstance(product.right, ast.Unary) and product.right.span == Span("f.cos", 1, 25, 1, 27)
    assert let.span == Span("f.cos", 1, 1, 1, 27)
    assert other.span == Span("f.cos", 2, 1, 3, 9)  # across the continuation
    assert other.value.span == Span("f.cos", 3, 3, 3, 9)


WORDS = [
    "MOVE", "TO", "BY", "CONTACT", "SLIDE", "INSERT", "COMPLY", "LET", "FRAME", "SPEED", "WAIT",
    "PROC", "END", "REPEAT", "TIMES", "CALL", "FORCE", "TORQUE", "DISTANCE", "UNTIL", "TIMEOUT",
    "IN", "VIA", "DEPTH", "STIFFNESS", "RPY", "AND", "OR", "NONE", "UP", "DOWN", "X", "RZ",
    "OBSTACLE", "REMOVE", "SPHERE", "AT", "RADIUS",
    "0", "2.5", "10 N", "25 mm", "0.3 m/s", "1e3", "hole", "p", "speed", "in",
    "(", ")", ",", "=", "+", "-", "*", ">", "<=", "\n", ";", "# c\n", "\\\n", "\t", "\r", "é", "@",
]  # fmt: skip


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(WORDS), max_size=14))
def test_fast_path_agrees_with_lark_or_gives_up_where_lark_fails(words: list[str]) -> None:
    text = " ".join(words)
    fast = _fast_parse(text)
    try:
        reference = _raw_parse(text)
    except Exception:  # noqa: BLE001 - any Lark failure: the fast path must have given up
        assert fast is None
        return
    assert fast is not None and fast == reference
