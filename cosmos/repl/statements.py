"""Inputs cut into statements, and the compile state kept true when a statement fails.

Also where a ``:load``-ed file sits in the transcript, to point messages back
into the file.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from cosmos.errors import CosmosError, Span
from cosmos.lang.compile.state import CompileState, frozen_map
from cosmos.plan import AddObstacle, RemoveObstacle, Segment, Step

REPL_FILE = "<repl>"
"""The file name typed input carries in spans and errors."""


def normalise_newlines(text: str) -> str:
    """CR LF and lone CR turned into LF, the one line break that spans count."""
    return text.replace("\r\n", "\n").replace("\r", "\n")


def statement_groups(steps: tuple[Step, ...]) -> Iterator[tuple[Step, ...]]:
    """Steps cut into statements: consecutive segments of one statement, or one scene change."""
    group: list[Step] = []
    for step in steps:
        if group and not (
            isinstance(step, Segment)
            and isinstance(group[-1], Segment)
            and group[-1].statement_index == step.statement_index
        ):
            yield tuple(group)
            group = []
        group.append(step)
    if group:
        yield tuple(group)


def state_after_failure(
    before: CompileState, after: CompileState, executed: list[Step], failed: Span | None
) -> CompileState:
    """The compile state that matches the arm after a statement failed or was interrupted.

    Args:
        before: The state before the statement.
        after: The state the compiler gave after it (as if it had succeeded).
        executed: The statement's steps that ran to the end before the failure.
        failed: Where the failed statement is written.

    Returns:
        ``after`` with no contact held (the arm holds its pose, no force) and the
        obstacles of ``before`` changed only by the scene steps that ran.
    """
    obstacles = dict(before.obstacles)
    for step in executed:
        if isinstance(step, AddObstacle):
            obstacles[step.name.casefold()] = step.span
        elif isinstance(step, RemoveObstacle):
            obstacles.pop(step.name.casefold(), None)
    released = failed if before.contact is not None else after.contact_released_by
    return dataclasses.replace(
        after,
        contact=None,
        contact_released_by=released,
        obstacles=frozen_map(obstacles),
    )


@dataclass(frozen=True)
class LoadedFile:
    """A program file run with ``:load``, placed in the transcript from ``first_line`` on."""

    path: Path
    text: str
    first_line: int

    def render(self, error: CosmosError) -> str:
        """The error as it reads in the file (its span moved from the transcript into the file)."""
        span = error.span
        offset = self.first_line - 1
        if span is None or span.file != REPL_FILE or not 1 <= span.line - offset <= self.text.count("\n") + 1:
            return error.render()
        moved = Span(str(self.path), span.line - offset, span.column, span.end_line - offset, span.end_column)
        return CosmosError(error.message, moved, self.text).render()
