"""Tab completion: keywords, the session's frames, obstacles and procedures, REPL commands, paths."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from functools import cache

from prompt_toolkit.completion import CompleteEvent, Completer, Completion, PathCompleter
from prompt_toolkit.document import Document

from cosmos.lang import CompileState
from cosmos.lang.parse.grammar import keywords
from cosmos.repl.commands import COMMANDS
from cosmos.repl.names import all_names

_NAME_FIRST_AFTER = frozenset({"TO", "AT", "IN", "VIA", "REMOVE", "CALL", "=", "+", "-", ","})
"""After these a name is more likely than a keyword, so names are offered first."""


@cache
def keyword_list() -> tuple[str, ...]:
    """Every keyword of the language, upper case, sorted."""
    return tuple(sorted(keywords()))


class ReplCompleter(Completer):
    """Completes the word before the cursor.

    Args:
        state: Returns the session's compile state now (names change as the session goes).
    """

    def __init__(self, state: Callable[[], CompileState]):
        self._state = state
        self._paths = PathCompleter(expanduser=True)

    def get_completions(self, document: Document, complete_event: CompleteEvent) -> Iterable[Completion]:
        """Completions of the word before the cursor."""
        before = document.text_before_cursor
        line = document.current_line_before_cursor
        if line.lstrip().startswith(":") and "\n" not in before.lstrip():
            yield from self._command(line.lstrip(), document, complete_event)
            return
        word = document.get_word_before_cursor(WORD=False)
        if word and not (word[0].isalpha() or word[0] == "_"):
            return
        previous = line[: len(line) - len(word)].rstrip().split()
        last = previous[-1].upper() if previous else ""
        names = [
            (name, kind)
            for name, kind in all_names(self._state()).items()
            if name.startswith(word.casefold())
        ]
        words = [(k, "keyword") for k in keyword_list() if k.startswith(word.upper())]
        if not previous:  # a statement or a procedure call starts the line
            names = [(n, k) for n, k in names if k == "procedure"]
        ordered = names + words if last in _NAME_FIRST_AFTER or last.endswith("=") else words + names
        for text, meta in ordered:
            yield Completion(text, start_position=-len(word), display_meta=meta)

    def _command(self, line: str, document: Document, complete_event: CompleteEvent) -> Iterable[Completion]:
        name, space, argument = line[1:].partition(" ")
        if not space:
            for command in COMMANDS.values():
                if command.name.startswith(name.lower()):
                    yield Completion(
                        ":" + command.name, start_position=-len(line), display_meta=command.summary
                    )
            return
        if name.lower() == "load":
            yield from self._paths.get_completions(Document(argument.lstrip()), complete_event)
