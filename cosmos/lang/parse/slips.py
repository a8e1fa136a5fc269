"""Common slips, recognised by the parser state they fail in, and what to say about each.

Like Lark's ``UnexpectedInput.match_examples``: each slip is parsed once per
process; a syntax error that fails in the same parser state, expecting the same
terminals, gets the slip's message.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from lark.exceptions import UnexpectedInput, UnexpectedToken

_DIRECTIONS = "+X -X +Y -Y +Z -Z, UP or DOWN"

# Common slips, recognised by the parser state they fail in (Lark match_examples).
_EXAMPLES: dict[str, list[str]] = {
    "expected TO or BY after MOVE: MOVE TO (0.5, 0.1, 0.3), MOVE TO hole, or MOVE BY (0, 0, -50 mm)": [
        "MOVE (0.5, 0.1, 0.3)",
        "MOVE 5 mm",
        "MOVE",
        "MOVE SPEED 3",
    ],
    f"CONTACT needs a direction first: {_DIRECTIONS} (as in CONTACT DOWN FORCE 10 N)": [
        "CONTACT FORCE 10 N",
        "CONTACT",
        "CONTACT (0, 0, 1)",
        "CONTACT 5",
    ],
    f"SLIDE needs a direction first: {_DIRECTIONS} (as in SLIDE +X BY 100 mm)": [
        "SLIDE BY 100 mm",
        "SLIDE",
        "SLIDE (1, 0, 0)",
        "SLIDE 5",
    ],
    f"INSERT needs a direction first: {_DIRECTIONS} (as in INSERT DOWN DEPTH 25 mm FORCE 15 N)": [
        "INSERT DEPTH 25 mm",
        "INSERT",
        "INSERT (0, 0, 1)",
        "INSERT 5",
    ],
    "expected '=' after the name: LET name = value": ["LET x 5", "LET x", "LET x (1, 2, 3)"],
    "expected '=' after the name: FRAME name = (x, y, z) RPY (roll, pitch, yaw)": [
        "FRAME f (0, 0, 0)",
        "FRAME f",
        "FRAME f 5",
    ],
    "LET needs a name: LET name = value": ["LET = 5", "LET 5 = 3", "LET"],
    "FRAME needs a name: FRAME name = (x, y, z)": ["FRAME = (0, 0, 0)", "FRAME 5", "FRAME"],
    "COMPLY needs axes (X Y Z RX RY RZ) or NONE, as in COMPLY X Y": [
        "COMPLY",
        "COMPLY STIFFNESS 3",
        "COMPLY 5",
        "COMPLY (1, 0, 0)",
    ],
    "OBSTACLE needs a name, then a shape (SPHERE, CYLINDER, BOX or PLANE): "
    "OBSTACLE ball SPHERE AT (0.4, 0.2, 0.5) RADIUS 50 mm": [
        "OBSTACLE ball AT (1, 2, 3)",
        "OBSTACLE ball",
        "OBSTACLE ball 5",
        "OBSTACLE",
        "OBSTACLE 5",
        "OBSTACLE (1, 2, 3)",
    ],
    "OBSTACLE REMOVE needs the obstacle's name": ["OBSTACLE REMOVE", "OBSTACLE REMOVE 3"],
    "UNTIL needs a comparison with > or <, as in UNTIL FORCE > 5 N": [
        "MOVE BY (0, 0, 1) UNTIL FORCE 5 N",
        "MOVE BY (0, 0, 1) UNTIL FORCE",
        "MOVE BY (0, 0, 1) UNTIL FORCE Z 5 N",
        "MOVE BY (0, 0, 1) UNTIL FORCE Z",
        "MOVE BY (0, 0, 1) UNTIL DISTANCE 4 mm",
        "MOVE BY (0, 0, 1) UNTIL DISTANCE",
    ],
    "UNTIL compares FORCE, TORQUE or DISTANCE with a value, as in UNTIL FORCE > 5 N": [
        "MOVE BY (0, 0, 1) UNTIL 5 N",
        "MOVE BY (0, 0, 1) UNTIL",
        "MOVE BY (0, 0, 1) UNTIL x > 3",
        "MOVE BY (0, 0, 1) UNTIL FORCE > 5 N AND",
        "MOVE BY (0, 0, 1) UNTIL FORCE > 5 N OR 3",
    ],
    "REPEAT needs a count: REPEAT 3 ... END": ["REPEAT\nEND", "REPEAT TIMES\nEND"],
    "PROC needs a name: PROC name ... END": ["PROC\nEND", "PROC 3\nEND"],
    "VIA needs one or more positions: MOVE TO p VIA a, b": [
        "MOVE TO (0, 0, 0) VIA",
        "MOVE TO (0, 0, 0) VIA SPEED 3",
    ],
    "CALL needs the name of a PROC": ["CALL", "CALL 3"],
    "ELSE without an IF: ELSE goes between IF condition ... and its END": ["ELSE", "ELSE\nWAIT 1 s"],
    "ON FAIL without a TRY: TRY ... ON FAIL ... END": ["ON FAIL", "ON FAIL\nWAIT 1 s"],
    "IF needs a condition, as in IF FORCE Z < -5 N ... END": ["IF\nEND", "IF 3\nEND"],
    "WHILE needs a condition, as in WHILE FORCE < 2 N ... END": ["WHILE\nEND", "WHILE 3\nEND"],
    "RETRY needs how many times at most: RETRY 3": ["TRY\nWAIT 1 s\nON FAIL\nRETRY\nEND"],
    "RPY needs three angles: RPY (180 deg, 0, 0)": ["FRAME f = (0, 0, 0) RPY"],
}


_PREFIXES = ("", "WAIT 1 s\n", "PROC p\n", "PROC p\nWAIT 1 s\n")
"""Each slip is also tried after a line and inside a PROC: the parser's stack
differs there, and parser states are compared whole."""

_example_errors: list[tuple[str, UnexpectedToken, set[str]]] | None = None


def match_slip(error: UnexpectedToken, parse: Callable[[str], Any]) -> str | None:
    """The label of the common slip that fails in the same parser state as ``error``.

    Like Lark's ``UnexpectedInput.match_examples``, but the examples are parsed
    once per process rather than on every error.
    """
    global _example_errors
    if _example_errors is None:
        found = []
        for label, examples in _EXAMPLES.items():
            for prefix in _PREFIXES:
                for example in examples:
                    try:
                        parse(prefix + example)
                    except UnexpectedToken as failure:
                        found.append((label, failure, set(failure.accepts or failure.expected)))
                    except UnexpectedInput:
                        pass
        _example_errors = found
    accepts = set(error.accepts or error.expected)
    candidate = None
    for label, example_error, example_accepts in _example_errors:
        if example_error.state == error.state and example_accepts == accepts:
            if example_error.token.type == error.token.type:
                return label
            candidate = candidate or label
    return candidate
