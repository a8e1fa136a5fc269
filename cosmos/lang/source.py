"""Reading program files: bytes to text, with decoding errors as spanned errors."""

from __future__ import annotations

from pathlib import Path

from cosmos.errors import ProgramError, Span, UsageError


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


def read_source(path: Path) -> str:
    """The text of a program file.

    Raises:
        UsageError: The file cannot be read.
        ProgramError: It is not UTF-8 text.
    """
    try:
        data = path.read_bytes()
    except OSError as error:
        raise UsageError(f"cannot read {path}: {error.strerror or error}") from None
    return decode_source(data, str(path))
