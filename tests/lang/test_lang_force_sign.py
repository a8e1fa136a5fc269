"""The checker warns when an UNTIL on a force component waits for the sign the move cannot produce."""

from __future__ import annotations

import pytest

from cosmos.lang import compile_program


def sign_warnings(source: str) -> list[str]:
    plan = compile_program(source, "w.cos")
    return [w.message for w in plan.warnings if "needs the opposite sign" in w.message]


@pytest.mark.parametrize(
    "statement",
    ["MOVE BY (0, 0, -40 mm) UNTIL FORCE Z > 3 N", "MOVE BY (0, 0, 40 mm) UNTIL FORCE Z < -3 N"],
)
def test_wrong_sign_is_warned(statement: str) -> None:
    assert len(sign_warnings(statement + "\n")) == 1


@pytest.mark.parametrize(
    "statement",
    [
        "MOVE BY (0, 0, -40 mm) UNTIL FORCE Z < -3 N",  # language.md's own form
        "MOVE BY (0, 0, -40 mm) UNTIL FORCE -Z > 3 N",
        "MOVE BY (0, 0, -40 mm) UNTIL FORCE > 3 N",  # a magnitude
        "MOVE BY (40 mm, 0, 0) UNTIL FORCE Z > 3 N",  # across the move: no telling
    ],
)
def test_right_or_undecidable_sign_is_not_warned(statement: str) -> None:
    assert sign_warnings(statement + "\n") == []
