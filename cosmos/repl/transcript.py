"""The session's transcript: everything typed, as one program text.

Each input is compiled as if it followed every earlier input in one file: its
text is preceded by as many blank lines as the transcript has. So line numbers
in errors, in the plan and in the log's ``line`` fields are lines of the
transcript, which is attached to the log as the session's program source when
the session ends.

Inputs that could not be compiled and REPL commands are kept as comments
(``# !`` and ``# :``), so the transcript stays a program that compiles and line
numbers stay put.
"""

from __future__ import annotations

from cosmos.lang.parse.source_file import readable

ERROR_PREFIX = "# ! "
"""Starts each line of an input that did not compile."""
COMMAND_PREFIX = "# "
"""Starts a REPL command line (``# :reset``)."""


class Transcript:
    """The lines typed so far."""

    def __init__(self) -> None:
        self._lines: list[str] = []

    @property
    def line_count(self) -> int:
        """Number of lines so far; the next input starts on line ``line_count + 1``."""
        return len(self._lines)

    def placed(self, text: str) -> str:
        """``text`` preceded by blank lines so that its first line is the next transcript line."""
        return "\n" * len(self._lines) + text

    def add_statements(self, text: str) -> None:
        """Record an input that compiled (it ran, or started to)."""
        self._lines += _lines(text)

    def add_rejected(self, text: str) -> None:
        """Record an input that did not compile, commented out line by line."""
        self._lines += [ERROR_PREFIX + line if line.strip() else "#" for line in _lines(text)]

    def add_command(self, command: str) -> None:
        """Record a REPL command (``:reset``) as a comment."""
        self._lines += [COMMAND_PREFIX + line for line in _lines(command)]

    def text(self) -> str:
        """The transcript, one input after the other, ending in a newline."""
        return "".join(line + "\n" for line in self._lines)


def _lines(text: str) -> list[str]:
    """Lines as the parser counts them: split at LF (inputs are normalised to it).

    Bytes that were not UTF-8 are shown as U+FFFD, so the transcript can be attached to the log.
    """
    return readable(text).removesuffix("\n").split("\n")
