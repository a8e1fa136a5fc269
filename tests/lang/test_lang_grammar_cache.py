"""The analysed grammar's cache: in the user's cache directory, optional, self-repairing."""

from __future__ import annotations

from pathlib import Path

import pytest

from cosmos.lang import ast
from cosmos.lang.parse import grammar

TEXT = "MOVE TO (0.5, 0.1, 0.3) SPEED 0.1 m/s\n"


def _fresh_parser() -> object:
    return grammar.lark_parser.__wrapped__()  # not the process's shared one


def test_no_cache_where_the_cache_directory_cannot_be_made(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches a read-only home (or install) stopping the parser from being built."""
    blocker = tmp_path / "not_a_directory"
    blocker.write_text("")
    monkeypatch.delenv("COSMOS_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    assert grammar._cache_file("grammar") is False
    (move,) = _fresh_parser().parse(TEXT)  # type: ignore[attr-defined]
    assert isinstance(move, ast.Move)


def test_a_broken_cache_file_is_rebuilt(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a truncated or foreign cache file breaking every later start."""
    monkeypatch.delenv("COSMOS_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    cache_file = Path(str(grammar._cache_file(grammar._grammar_text())))
    assert cache_file.parent == tmp_path / "cosmos"
    cache_file.write_bytes(b"not a cache\n")
    (move,) = _fresh_parser().parse(TEXT)  # type: ignore[attr-defined]
    assert isinstance(move, ast.Move)
    assert cache_file.stat().st_size > 1000  # written again, whole
    (again,) = _fresh_parser().parse(TEXT)  # type: ignore[attr-defined]  # loaded from it
    assert again == move


def test_the_cache_directory_chosen_for_cosmos_holds_the_grammar(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches the analysed grammar kept in ``~/.cache`` when ``COSMOS_CACHE_DIR`` names another
    directory (as the kernels and the rest are): a first run in a fresh cache directory then found
    the grammar analysed already, and a home that cannot be written was written to anyway."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path / "chosen"))
    cache_file = Path(str(grammar._cache_file(grammar._grammar_text())))
    assert cache_file.parent == tmp_path / "chosen"
    (move,) = _fresh_parser().parse(TEXT)  # type: ignore[attr-defined]
    assert isinstance(move, ast.Move)
    assert cache_file.is_file() and not (tmp_path / "xdg").exists()
