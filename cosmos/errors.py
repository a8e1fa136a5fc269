"""The one root exception of cosmos and the source spans errors point at.

Every error a user can cause derives from :class:`CosmosError`. Errors about
program text carry a :class:`Span` and render as ``file:line:col: message``,
the source line, and a caret under the span.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Span:
    """A region of a source file; lines and columns count from 1, end is exclusive.

    Attributes:
        file: Path of the source as the user named it (``<repl>`` for typed input).
        line: Line of the first character.
        column: Column of the first character.
        end_line: Line of the character after the span.
        end_column: Column of the character after the span.
    """

    file: str
    line: int
    column: int
    end_line: int
    end_column: int

    @property
    def location(self) -> str:
        """``file:line:col``."""
        return f"{self.file}:{self.line}:{self.column}"


SHOWN_LINE_CHARS = 100
"""Of a longer program line, an error shows this many characters about its caret."""


class CosmosError(Exception):
    """Root of every error cosmos raises for a user's mistake or a failed task.

    Args:
        message: What went wrong, in words a user knows, with the fix if there is one.
        span: Where in the program text, if the error concerns it.
        source: The full program text, used to print the offending line.
    """

    def __init__(self, message: str, span: Span | None = None, source: str | None = None):
        super().__init__(message)
        self.message = message
        self.span = span
        self.source = source

    def with_source(self, source: str) -> CosmosError:
        """Attach the program text (if not attached yet) and return self."""
        if self.source is None:
            self.source = source
        return self

    def render(self) -> str:
        """``file:line:col: message``, then the source line and a caret under the span."""
        if self.span is None:
            return self.message
        head = f"{self.span.location}: {self.message}"
        if self.source is None:
            return head
        lines = self.source.splitlines()
        if not 1 <= self.span.line <= len(lines):
            return head
        text = lines[self.span.line - 1].expandtabs(1)
        start = max(self.span.column - 1, 0)
        if self.span.end_line == self.span.line:
            width = max(self.span.end_column - self.span.column, 1)
        else:
            width = max(len(text) - start, 1)
        if len(text) > SHOWN_LINE_CHARS:  # a window of the line about the caret, cut ends marked
            left = max(0, min(start - SHOWN_LINE_CHARS // 4, len(text) - SHOWN_LINE_CHARS))
            right = left + SHOWN_LINE_CHARS
            width = max(1, min(width, right - start))
            cut = "..." if left else ""
            text = cut + text[left:right] + ("..." if right < len(text) else "")
            start += len(cut) - left
        return f"{head}\n    {text}\n    {' ' * start}{'^' * width}"

    def __str__(self) -> str:
        return self.render()


class ProgramError(CosmosError):
    """A syntax, name, unit or check error in program text."""


class TaskFailure(CosmosError):
    """A statement failed on the arm: timeout, no contact, jam, unreachable, local minimum."""


class UsageError(CosmosError):
    """Wrong use of the command line: a missing file, a bad option value."""
