"""Reading program files: one bounded reader for ``check``, ``run`` and the REPL's ``:load``.

:func:`read_program` opens regular files only (a FIFO, a device such as
``/dev/zero`` or a directory is refused without waiting on it), reads at most
:data:`MAX_PROGRAM_BYTES`, decodes UTF-8 with or without a byte-order mark,
refuses binary data, and turns CR LF and lone CR into LF, so every command sees
the same text and the same line numbers.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from cosmos.errors import ProgramError, Span, UsageError

MAX_PROGRAM_BYTES = 1_000_000
"""Largest program file read (1 MB, some 40,000 lines)."""

_BINARY = re.compile(rb"[\x00-\x08\x0b\x0e-\x1f\x7f]")
"""Control characters no program text holds (tab, line breaks and form feed are text)."""


def decode_source(data: bytes, file: str) -> str:
    """Program text from a file's bytes (UTF-8, an optional byte-order mark dropped).

    Raises:
        ProgramError: The bytes are not UTF-8; the span points at the first bad byte.
    """
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        start = error.start  # counts from the start of the data, byte-order mark included
        before = data[:start]
        line = before.count(b"\n") + 1
        column = len(before.rsplit(b"\n", 1)[-1].decode("utf-8", errors="replace")) + 1
        shown = data[start : start + 1].hex()
        raise ProgramError(
            f"the program is not UTF-8 text (byte 0x{shown} cannot be read); is this the right file?",
            Span(file, line, column, line, column + 1),
            before.decode("utf-8", errors="replace") + "\n",
        ) from None


def check_typed_text(text: str, file: str, first_line: int) -> None:
    """Refuse typed text holding bytes that were not UTF-8 (read with ``surrogateescape``).

    Args:
        text: The input, as read from a pipe or terminal (each bad byte a lone surrogate, U+DC80 to U+DCFF).
        file: Its name for messages (``<repl>``).
        first_line: The line number of its first line.

    Raises:
        ProgramError: At the first bad byte, as :func:`decode_source` does for a file.
    """
    bad = next((i for i, c in enumerate(text) if "\udc80" <= c <= "\udcff"), None)
    if bad is None:
        return
    before = text[:bad]
    line = first_line + before.count("\n")
    column = len(before.rsplit("\n", 1)[-1]) + 1
    shown = text[bad].encode("utf-8", "surrogateescape").hex()
    raise ProgramError(
        f"the input is not UTF-8 text (byte 0x{shown} cannot be read)",
        Span(file, line, column, line, column + 1),
        "\n" * (first_line - 1) + readable(text),
    )


def readable(text: str) -> str:
    """``text`` with bytes that were not UTF-8 shown as U+FFFD (so it can be written as UTF-8)."""
    return text.encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def _kind(mode: int) -> str:
    """What a file that is not a regular file is, in words."""
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _read_bounded(path: Path) -> bytes:
    """The bytes of a regular file of at most :data:`MAX_PROGRAM_BYTES`.

    Raises:
        UsageError: Not a regular file, too large, or unreadable.
    """
    too_large = f"{path}: the file is larger than {MAX_PROGRAM_BYTES // 1_000_000} MB; a program is smaller"
    try:
        # O_NONBLOCK: opening a FIFO does not wait for a writer (it is refused just below)
        descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as error:
        raise UsageError(f"cannot read {path}: {error.strerror or error}") from None
    try:
        mode = os.fstat(descriptor).st_mode
        if not stat.S_ISREG(mode):
            raise UsageError(f"{path}: {_kind(mode)}, not a program file")
        if os.fstat(descriptor).st_size > MAX_PROGRAM_BYTES:
            raise UsageError(too_large)
        chunks: list[bytes] = []
        size = 0
        while size <= MAX_PROGRAM_BYTES:  # the size said may be wrong (/proc) or grow
            chunk = os.read(descriptor, MAX_PROGRAM_BYTES + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > MAX_PROGRAM_BYTES:
            raise UsageError(too_large)
        return b"".join(chunks)
    except OSError as error:
        raise UsageError(f"cannot read {path}: {error.strerror or error}") from None
    finally:
        os.close(descriptor)


def read_program(path: Path | str) -> str:
    """The text of a program file, read with bounds; line breaks are LF.

    Raises:
        UsageError: Not a regular file, larger than :data:`MAX_PROGRAM_BYTES`,
            unreadable, or binary data; one line naming the path, no content.
        ProgramError: It is not UTF-8 text (located at the first bad byte).
    """
    path = Path(path)
    data = _read_bounded(path)
    if _BINARY.search(data):
        raise UsageError(f"{path}: binary data (control characters), not a program file")
    text = decode_source(data, str(path))
    return text.replace("\r\n", "\n").replace("\r", "\n")


def read_source(path: Path) -> str:
    """The text of a program file (:func:`read_program`; the name kept for callers).

    Raises:
        UsageError: The file cannot be read as a program.
        ProgramError: It is not UTF-8 text.
    """
    return read_program(path)
