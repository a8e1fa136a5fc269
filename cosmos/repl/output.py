"""Where the REPL writes: plain lines, or coloured on a terminal."""

from __future__ import annotations

import enum
from typing import TextIO


class Tone(enum.Enum):
    """What kind of message a line is; sets its colour on a terminal."""

    PLAIN = ""
    OK = "\x1b[32m"
    NOTE = "\x1b[2m"
    WARNING = "\x1b[33m"
    ERROR = "\x1b[31m"


_RESET = "\x1b[0m"


class Printer:
    """Writes messages to a text stream, one call per message, flushed at once.

    Args:
        stream: Where to write (the terminal, or a ``StringIO`` in tests).
        color: Colour the messages with ANSI escapes.
    """

    def __init__(self, stream: TextIO, color: bool = False):
        self.stream = stream
        self.color = color

    def write(self, text: str, tone: Tone = Tone.PLAIN) -> None:
        """Write ``text`` and a newline."""
        if self.color and tone is not Tone.PLAIN:
            text = f"{tone.value}{text}{_RESET}"
        self.stream.write(text + "\n")
        self.stream.flush()

    def lines(self, lines: list[str], tone: Tone = Tone.PLAIN) -> None:
        """Write several lines."""
        for line in lines:
            self.write(line, tone)
