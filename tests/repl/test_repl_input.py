"""Typing without the arm: when Enter runs an input, indentation, completion, highlighting."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from prompt_toolkit.completion import CompleteEvent
from prompt_toolkit.document import Document
from prompt_toolkit.history import FileHistory, InMemoryHistory

from cosmos.lang import Compiler, parse_program
from cosmos.repl.completion import ReplCompleter
from cosmos.repl.highlight import highlight_line
from cosmos.repl.multiline import input_complete, next_indent
from cosmos.repl.output import Printer
from cosmos.repl.reader import history_path, open_history
from cosmos.workcell import fixture_frames


@pytest.mark.parametrize(
    ("text", "complete"),
    [
        ("MOVE BY (0, 0, -20 mm)", True),
        ("", True),
        (":load some file.cos", True),
        ("PROC pick", False),
        ("PROC pick\n    MOVE BY (0, 0, -5 mm)", False),
        ("PROC pick\n    MOVE BY (0, 0, -5 mm)\nEND", True),
        ("repeat 3 times\n    WAIT 1 s", False),
        ("REPEAT 3\n  REPEAT 2\n    WAIT 1 s\n  END", False),
        ("REPEAT 3\n  REPEAT 2\n    WAIT 1 s\n  END\nEND", True),
        ("MOVE TO (0.5,", True),  # a statement ends with its line: the parser wants ')'
        ("MOVE TO (0.5, 0.1, 0.3) \\", False),
        ("MOVE TO (0.5, \\\n  0.1, 0.3)", True),
        ("MOVE TO (0.5, 0.1, 0.3) # a comment \\", True),
        ("PROC pick\n    \n    ", True),  # two empty lines hand an open block over
        ("MOVE SPED 3", True),  # a mistake is complete: Enter shows it
        # A TRY typed line by line ran "TRY" alone ("this TRY has no END"): it wants its ON FAIL.
        ("TRY", False),
        ("TRY\n    CONTACT DOWN FORCE 5 N TIMEOUT 1 s", False),
        ("TRY\n    CONTACT DOWN FORCE 5 N TIMEOUT 1 s\nON FAIL", False),
        ("TRY\n    CONTACT DOWN FORCE 5 N TIMEOUT 1 s\nON FAIL\n    MOVE BY (0, 0, 10 mm)\nEND", True),
        ("IF FORCE Z < -3 N\n    MOVE BY (0, 0, 1 mm)\nELSE", False),
        ("WHILE FORCE > 1 N MAX 3", False),
    ],
)
def test_enter_runs_only_complete_inputs(text: str, complete: bool) -> None:
    assert input_complete(text) is complete


def test_complete_blocks_parse_and_open_ones_do_not() -> None:
    """Cross-check with the parser itself: a complete block parses, the same block cut before END does not."""
    block = "PROC pick\n    MOVE BY (0, 0, -5 mm)\n    WAIT 1 s\nEND"
    parse_program(block, "<test>")
    cut = block.rsplit("\n", 1)[0]
    with pytest.raises(Exception, match="no END"):
        parse_program(cut, "<test>")
    assert input_complete(block) and not input_complete(cut)


def test_indentation_follows_blocks() -> None:
    assert next_indent("PROC pick") == "    "
    assert next_indent("    REPEAT 2") == "        "
    assert next_indent("        WAIT 1 s") == "        "
    assert next_indent("    END") == ""
    assert next_indent("TRY") == next_indent("ON FAIL") == next_indent("IF FORCE > 1 N") == "    "


def _completions(text: str) -> list[str]:
    compiler = Compiler(fixture_frames())
    state = compiler.compile_text(
        "FRAME above = table + (0, 0, 80 mm)\nPROC pick\nWAIT 1 s\nEND", compiler.initial_state()
    ).state
    completer = ReplCompleter(lambda: state)
    return [
        c.text for c in completer.get_completions(Document(text), CompleteEvent(completion_requested=True))
    ]


def test_completion_of_keywords_names_and_commands() -> None:
    assert _completions("MO") == ["MOVE", "MOVING"]
    assert _completions("con")[0] == "CONTACT"
    after_to = _completions("MOVE TO ")
    assert after_to[:5] == ["world", "table", "hole", "slope", "above"]  # names before keywords
    assert "TO" in after_to
    assert _completions("MOVE TO ab") == ["above"]
    assert _completions("pic") == ["pick"]  # a procedure call starts a line ("pi": PITCH too)
    assert _completions(":st") == [":state"]
    assert _completions(":") == [":help", ":state", ":frames", ":load", ":reset", ":log", ":live", ":quit"]
    assert _completions("MOVE BY (0, 0, 1") == []


def test_highlighting_classes() -> None:
    fragments = highlight_line("MOVE TO above SPEED 20 mm/s  # slow", {"above"})
    styled = {text: style for style, text in fragments if text.strip()}
    assert styled == {
        "MOVE": "class:statement",
        "TO": "class:keyword",
        "above": "class:name",
        "SPEED": "class:keyword",  # a clause here, not the SPEED statement
        "20 mm/s": "class:number",
        "# slow": "class:comment",
    }
    assert "".join(text for _, text in fragments) == "MOVE TO above SPEED 20 mm/s  # slow"
    assert highlight_line("CONTACT -X", set())[-1] == ("class:direction", "-X")
    assert highlight_line("SPEED 0.2; WAIT 1", set())[-1 - 2] == ("class:statement", "WAIT")


def test_load_completes_file_names(tmp_path: Path) -> None:
    (tmp_path / "peg_in_hole.cos").write_text("")
    typed = f":load {tmp_path}/peg"
    completer = ReplCompleter(lambda: Compiler(fixture_frames()).initial_state())
    (completion,) = completer.get_completions(Document(typed), CompleteEvent(completion_requested=True))
    assert (
        typed[: len(typed) + completion.start_position] + completion.text
        == f":load {tmp_path}/peg_in_hole.cos"
    )


def test_history_file_from_the_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    printer = Printer(io.StringIO())
    monkeypatch.setenv("COSMOS_HISTORY", str(tmp_path / "sub" / "history"))
    assert history_path() == tmp_path / "sub" / "history"
    history = open_history(history_path(), printer)
    assert isinstance(history, FileHistory)
    history.store_string("MOVE BY (0, 0, 1 mm)")
    assert "+MOVE BY (0, 0, 1 mm)" in (tmp_path / "sub" / "history").read_text()


def test_unwritable_history_is_kept_in_memory(tmp_path: Path) -> None:
    stream = io.StringIO()
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert isinstance(open_history(blocker / "history", Printer(stream)), InMemoryHistory)
    assert "history is not kept" in stream.getvalue()
