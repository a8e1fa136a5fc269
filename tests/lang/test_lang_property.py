"""No input, however broken, escapes as anything but a CosmosError with a span
inside the file: random token sequences, random edits of valid programs, raw bytes."""

from __future__ import annotations

import re
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lang_support import FIXTURES

from cosmos.errors import CosmosError
from cosmos.lang import compile_program, decode_source
from cosmos.plan import Plan

DOCS = Path(__file__).parents[2] / "docs" / "language.md"
PROGRAMS = [block for block in re.findall(r"```cosmos\n(.*?)```", DOCS.read_text(), re.S)]

TOKENS = [
    # statements and clauses
    "MOVE", "TO", "BY", "CONTACT", "SLIDE", "INSERT", "COMPLY", "OBSTACLE", "REMOVE", "LET",
    "FRAME", "SPEED", "WAIT", "PROC", "END", "REPEAT", "TIMES", "CALL", "FORCE", "TORQUE",
    "DISTANCE", "UNTIL", "TIMEOUT", "IN", "VIA", "DEPTH", "STIFFNESS", "DAMPING", "AT", "RADIUS",
    "HEIGHT", "SIZE", "MOVING", "NORMAL", "INFLUENCE", "GAIN", "SPHERE", "CYLINDER", "BOX",
    "PLANE", "NONE", "RPY", "AND", "OR",
    # directions and axes
    "UP", "DOWN", "X", "Y", "Z", "RX", "RY", "RZ", "+X", "-Z",
    # values
    "0", "1", "-3", "0.5", "10 N", "25 mm", "0.3 m/s", "90 deg", "2 s", "400 N/m", "5 Nm",
    "20 Nm/rad", "1e999", "0 s", "-5 N", "10 mx",
    # names
    "hole", "table", "slope", "p", "pick", "speed",
    # punctuation and layout
    "(", ")", ",", "=", "+", "-", "*", ">", "<", ">=", "\n", "\n", ";", "#", "\\\n", "\t",
    # junk
    '"', "@", "\x00", "é", "\r",
]  # fmt: skip


def assert_clean(source: str) -> None:
    """Compiles, or fails with a CosmosError whose span lies inside the text."""
    try:
        result = compile_program(source, "fuzz.cos", FIXTURES)
    except CosmosError as error:
        assert error.span is not None, error.message
        lines = max(len(source.splitlines()), 1)
        assert 1 <= error.span.line <= lines + 1, (error.span, source)
        assert error.span.column >= 1
        assert (error.span.end_line, error.span.end_column) >= (error.span.line, error.span.column)
        assert error.render().startswith("fuzz.cos:")
    else:
        assert isinstance(result, Plan)


@settings(max_examples=90, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(TOKENS), max_size=30))
def test_random_token_sequences(tokens: list[str]) -> None:
    assert_clean(" ".join(tokens))


@st.composite
def mutated_program(draw: st.DrawFn) -> str:
    text = draw(st.sampled_from(PROGRAMS))
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["delete", "insert", "replace", "duplicate_line", "swap_lines"]))
        position = draw(st.integers(0, len(text)))
        if kind == "delete":
            text = text[:position] + text[position + draw(st.integers(1, 8)) :]
        elif kind == "insert":
            text = text[:position] + draw(st.sampled_from(TOKENS)) + text[position:]
        elif kind == "replace":
            text = text[:position] + draw(st.text(max_size=3)) + text[position + 1 :]
        else:
            lines = text.splitlines(keepends=True)
            if len(lines) > 1:
                i = draw(st.integers(0, len(lines) - 1))
                j = draw(st.integers(0, len(lines) - 1))
                if kind == "duplicate_line":
                    lines.insert(j, lines[i])
                else:
                    lines[i], lines[j] = lines[j], lines[i]
            text = "".join(lines)
    return text


@settings(max_examples=90, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_program())
def test_mutations_of_valid_programs(source: str) -> None:
    assert_clean(source)


@settings(max_examples=20, deadline=None)
@given(st.binary(max_size=200))
def test_raw_bytes(data: bytes) -> None:
    try:
        source = decode_source(data, "fuzz.cos")
    except CosmosError as error:
        assert error.span is not None and error.span.line >= 1
        assert "not UTF-8" in error.render()
        return
    assert_clean(source)


def test_pathological_inputs() -> None:
    for source in (
        "",
        "(",
        ")",
        "(" * 10_000,
        "MOVE BY (0, 0, " + "+".join(["1 mm"] * 10_000) + ")",
        "MOVE BY (0, 0, " + "-" * 5_000 + "1 mm)",
        "MOVE BY (0, 0, 1 mm) UNTIL " + " AND ".join(["FORCE > 1 N"] * 3_000),
        "REPEAT 1000000\nWAIT 1 s\nEND",
        "PROC a\nCALL b\nEND\nPROC b\nCALL a\nEND\nCALL a",
        "\x00\x01\x02",
        "MOVE TO hole\r\nWAIT 1 s\rWAIT 2 s",
    ):
        assert_clean(source)
