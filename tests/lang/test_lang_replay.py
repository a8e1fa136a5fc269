"""Replayed statements (cosmos/lang/lalr_run.py) against Lark: same trees, same spans.

The fast parser runs the first statement of each shape through the LALR table
and replays what it did for later statements of that shape. Programs that repeat
shapes with other names, numbers, units, keyword spellings and layouts, inside
and outside blocks, must still give exactly the tree Lark builds.
"""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cosmos.lang.parser import _fast_parse, _raw_parse

NUMBERS = ["1", "2.5", "10 N", "25 mm", "0.3 m/s", ".5e1 deg", "3 Nm", "7"]
NAMES = ["hole", "p", "speed", "in", "force", "x"]  # keywords too, where no keyword fits
CALLED = ["hole", "p", "Pick_2"]

STATEMENTS = [
    "MOVE TO {n} + ({a}, {b}, {a}) SPEED {a}",
    "move to ({a}, {b}, {a}) rpy ({b}, 0, {a}) via ({a}, {a}, {b}), {n} in {a}",
    "MOVE BY ({a}, {b}, {a}) UNTIL FORCE Z > {a} OR DISTANCE > {b}",
    "CONTACT DOWN FORCE {a} SPEED {b} TIMEOUT {a}",
    "SLIDE +X BY {a} FORCE {b} UNTIL (FORCE X > {a} AND TORQUE RZ < {b}) OR DISTANCE >= {a}",
    "INSERT DOWN DEPTH {a} FORCE {b} COMPLY X Y RX RY TIMEOUT {a}",
    "WAIT {a}",
    "WAIT UNTIL FORCE > {a} TIMEOUT {b}",
    "COMPLY X Y STIFFNESS {a} DAMPING {b}",
    "COMPLY NONE",
    "LET {n} = -({a}, {b}, {a}) * {b} - {n}",
    "FRAME {n} = {n} + ({a}, {a}, {b}) RPY (0, {a}, 0)",
    "SPEED {n}",
    "{c}",
    "CALL {c}",
    "OBSTACLE {n} SPHERE AT ({a}, {b}, {a}) RADIUS {a}",
    "OBSTACLE REMOVE {n}",
]
ENDS = ["\n", "\n\n", " # note\n", ";", " ; ", "\r\n"]


@st.composite
def statement(draw: st.DrawFn) -> str:
    template = draw(st.sampled_from(STATEMENTS))
    text = template.format(
        n=draw(st.sampled_from(NAMES)),
        c=draw(st.sampled_from(CALLED)),
        a=draw(st.sampled_from(NUMBERS)),
        b=draw(st.sampled_from(NUMBERS)),
    )
    return text + draw(st.sampled_from(ENDS))


@st.composite
def program(draw: st.DrawFn) -> str:
    parts: list[str] = []
    for _ in range(draw(st.integers(1, 6))):
        body = "".join(draw(st.lists(statement(), min_size=1, max_size=6)))
        kind = draw(st.sampled_from(["plain", "proc", "repeat"]))
        if kind == "proc":
            body = f"PROC {draw(st.sampled_from(CALLED))}\n{body}\nEND PROC\n"
        elif kind == "repeat":
            body = f"REPEAT {draw(st.sampled_from(NUMBERS))} TIMES\n{body}END\n"
        parts.append(body)
    return "".join(parts)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program())
def test_replayed_statements_build_the_tree_lark_builds(text: str) -> None:
    fast = _fast_parse(text)
    assert fast is not None, f"the fast path gave up on a valid program: {text!r}"
    assert fast == _raw_parse(text)


def test_a_repeated_statement_keeps_its_own_tokens_and_places() -> None:
    text = "MOVE TO (1, 2, 3) SPEED 1 m/s\n  move to (4, 5, 6) speed 2 mm/s\nMOVE TO (7,8,9) SPEED 3 m/s\n"
    fast = _fast_parse(text)
    assert fast is not None
    assert fast == _raw_parse(text)
    assert [s.span.line for s in fast] == [1, 2, 3]
    assert fast[1].span.column == 3
