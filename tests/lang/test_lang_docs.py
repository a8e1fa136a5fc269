"""Every ```cosmos example of docs/language.md passes ``cosmos check`` without warnings."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from cosmos.cli import cli

DOCS = Path(__file__).parents[2] / "docs" / "language.md"
BLOCKS = re.findall(r"```cosmos\n(.*?)```", DOCS.read_text(), re.S)


def test_the_reference_has_examples() -> None:
    assert len(BLOCKS) >= 10


@pytest.mark.parametrize("block", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_docs_example_checks_cleanly(block: str, tmp_path: Path) -> None:
    path = tmp_path / "example.cos"
    path.write_text(block)
    result = CliRunner().invoke(cli, ["check", str(path)])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    assert result.exit_code == 0, result.output
    assert "warning" not in result.stderr, result.stderr
