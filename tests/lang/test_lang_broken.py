"""Each file in broken/ is a program with one defect, named after it; its first
line says where the error must point and what it must say:
``# expect: LINE:COLUMN message fragment``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from lang_support import FIXTURES

from cosmos.errors import CosmosError, ProgramError
from cosmos.lang import compile_program

BROKEN = sorted((Path(__file__).parent / "broken").glob("*.cos"))
EXPECT = re.compile(r"# expect: (\d+):(\d+) (.+)")


def test_the_corpus_is_there() -> None:
    assert len(BROKEN) >= 50


@pytest.mark.parametrize("path", BROKEN, ids=lambda p: p.stem)
def test_broken_program_reports_its_defect(path: Path) -> None:
    source = path.read_text()
    match = EXPECT.match(source.splitlines()[0])
    assert match, f"{path.name} has no '# expect: line:col message' header"
    line, column, fragment = int(match[1]), int(match[2]), match[3]
    with pytest.raises(ProgramError) as caught:
        compile_program(source, path.name, FIXTURES)
    error = caught.value
    assert error.span is not None
    assert (error.span.line, error.span.column) == (line, column), error.render()
    assert fragment in error.message, error.render()
    rendered = error.render()
    assert rendered.startswith(f"{path.name}:{line}:{column}: ")
    assert "^" in rendered.splitlines()[-1]


def test_errors_in_independent_statements_are_all_reported() -> None:
    source = "CONTACT DOWN FORCE 10 mm\nWAIT 0 s\nMOVE TO hoel\n"
    with pytest.raises(ProgramError) as caught:
        compile_program(source, "many.cos", FIXTURES)
    rendered = caught.value.render()
    assert [e.span.line for e in caught.value.errors] == [1, 2, 3]  # type: ignore[attr-defined]
    assert rendered.count("many.cos:") == 3


def test_a_broken_definition_is_reported_once() -> None:
    source = "LET d = 5 parsecs\nMOVE BY (0, 0, d)\nMOVE BY (d, 0, 0)\n"
    with pytest.raises(CosmosError) as caught:
        compile_program(source, "once.cos", FIXTURES)
    assert caught.value.render().count("once.cos:") == 1
