"""Reading inputs: a prompt_toolkit prompt on a terminal, plain lines from a pipe.

Either reader is a callable that returns one complete input (see
:mod:`cosmos.repl.multiline`) and raises ``EOFError`` at the end (Ctrl-D) and
``KeyboardInterrupt`` for a Ctrl-C at the prompt.

The prompt is one multi-line buffer: Enter runs the input when it is complete
and otherwise opens a new, indented line, so a whole PROC ... END is edited,
run and recalled from history as one piece.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

from prompt_toolkit import PromptSession
from prompt_toolkit.history import FileHistory, History, InMemoryHistory
from prompt_toolkit.input import Input
from prompt_toolkit.key_binding import KeyBindings, KeyPressEvent
from prompt_toolkit.output import Output

from cosmos.repl.completion import ReplCompleter
from cosmos.repl.engine import ReplEngine
from cosmos.repl.highlight import STYLE, CosmosLexer
from cosmos.repl.multiline import input_complete, next_indent
from cosmos.repl.names import all_names
from cosmos.repl.output import Printer, Tone

PROMPT = "cosmos> "
HISTORY_ENV = "COSMOS_HISTORY"
"""Environment variable naming the history file (default ``~/.cosmos_history``)."""

Reader = Callable[[], str]


def history_path() -> Path:
    """``$COSMOS_HISTORY``, else ``~/.cosmos_history``."""
    return Path(os.environ.get(HISTORY_ENV) or Path.home() / ".cosmos_history").expanduser()


def open_history(path: Path, printer: Printer) -> History:
    """A history kept in ``path``; in memory only (with a note) if the file cannot be written."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "a", encoding="utf-8"):
            pass
    except OSError as error:
        printer.write(f"history is not kept: cannot write {path}: {error.strerror or error}", Tone.NOTE)
        return InMemoryHistory()
    return FileHistory(str(path))


def key_bindings() -> KeyBindings:
    """Enter runs a complete input or opens a new line; Esc Enter runs the input as it is."""
    bindings = KeyBindings()

    @bindings.add("enter")
    @bindings.add("c-j")
    def _enter(event: KeyPressEvent) -> None:
        buffer = event.current_buffer
        state = buffer.complete_state
        if state is not None and state.current_completion is not None:
            buffer.complete_state = None  # keep the chosen completion, go on typing
            return
        document = buffer.document
        on_last_line = document.cursor_position_row == document.line_count - 1
        if on_last_line and input_complete(buffer.text):
            buffer.validate_and_handle()
        else:
            buffer.insert_text("\n" + next_indent(document.current_line_before_cursor))

    @bindings.add("escape", "enter")
    def _run_now(event: KeyPressEvent) -> None:
        event.current_buffer.validate_and_handle()

    return bindings


def _continuation(width: int, line_number: int, wrap_count: int) -> str:
    return "." * (width - 1) + " "


def prompt_reader(
    engine: ReplEngine,
    history: History,
    input: Input | None = None,
    output: Output | None = None,
) -> Reader:
    """A reader on a prompt_toolkit prompt with history, completion, highlighting and a toolbar.

    Args:
        engine: The session (names for completion and highlighting, the arm for the toolbar).
        history: Where inputs are remembered.
        input: Keyboard input (None: the terminal; a pipe input in tests).
        output: Screen output (None: the terminal; ``DummyOutput`` in tests).
    """
    toolbar = [""]
    session: PromptSession[str] = PromptSession(
        PROMPT,
        multiline=True,
        key_bindings=key_bindings(),
        history=history,
        completer=ReplCompleter(lambda: engine.state),
        complete_while_typing=False,
        lexer=CosmosLexer(lambda: set(all_names(engine.state))),
        style=STYLE,
        include_default_pygments_style=False,
        bottom_toolbar=lambda: toolbar[0],
        prompt_continuation=_continuation,
        input=input,
        output=output,
    )

    def read() -> str:
        toolbar[0] = " " + engine.status().toolbar()
        return session.prompt()

    return read


def plain_reader(stream: TextIO, printer: Printer) -> Reader:
    """A reader of lines from a pipe or file, each input echoed after the prompt."""

    def read() -> str:
        lines: list[str] = []
        while True:
            line = stream.readline()
            if not line:
                if lines:
                    break
                raise EOFError
            lines.append(line.rstrip("\r\n"))
            if input_complete("\n".join(lines)):
                break
        text = "\n".join(lines)
        if text.strip():
            shown = [PROMPT + lines[0]] + ["." * (len(PROMPT) - 1) + " " + line for line in lines[1:]]
            printer.lines(shown)
        return text

    return read
