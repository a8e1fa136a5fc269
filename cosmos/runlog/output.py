"""Output files (``--log``, ``--recover``, ``--plot``, ``--video``): opened once, errors in one line.

The rules, the same for every output:

- an existing file is not overwritten unless the user said ``--force``;
- a directory, a device, a FIFO or anything else that is not a regular file is
  refused (``--log /dev/full`` does not get as far as the writer);
- a file the command reads (the program, the log replayed) is never an output;
- missing parent directories are created only for the default ``logs/``
  directory; a path the user typed must be in a directory that exists;
- every ``OSError`` becomes a :class:`~cosmos.errors.UsageError` (exit 2) that
  names the path and the reason.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from typing import BinaryIO

from cosmos.errors import UsageError


def cannot_write(path: Path, error: OSError, what: str) -> UsageError:
    """The one-line error for an ``OSError`` while writing ``path``, the file of ``what``."""
    reason = error.strerror or str(error) or type(error).__name__
    return UsageError(f"{path}: cannot write {what}: {reason}")


def check_output(
    path: Path, *, what: str, force: bool, make_parents: bool = False, reads: tuple[Path, ...] = ()
) -> None:
    """Refuse ``path`` as an output unless it can be written under the rules above.

    Args:
        path: The output file.
        what: What it holds, for messages: "the log", "the plot".
        force: Whether an existing regular file may be overwritten.
        make_parents: Create missing parent directories (only for the default ``logs/``).
        reads: The files the command reads: ``--force`` does not let it overwrite them.

    Raises:
        UsageError: If the path is refused, naming it and the reason.
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        info = None
    except OSError as error:
        raise cannot_write(path, error, what) from None
    if info is not None:
        if stat.S_ISDIR(info.st_mode):
            raise UsageError(f"{path}: is a directory; give a file name")
        if not stat.S_ISREG(info.st_mode):
            raise UsageError(f"{path}: not a regular file; give a file name")
        if any(read.exists() and os.path.samefile(path, read) for read in reads):
            raise UsageError(f"{path}: is a file this command reads; give {what} another name")
        if not force:
            raise UsageError(f"{path}: already exists; pass --force to overwrite it")
        return
    parent = path.parent
    if make_parents:
        try:
            parent.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise cannot_write(path, error, what) from None
    elif not parent.is_dir():
        raise UsageError(f"{path}: no such directory {parent}; create it first")


def open_output(
    path: Path, *, what: str, force: bool, make_parents: bool = False, buffered: bool = True
) -> BinaryIO:
    """Open ``path`` for writing under the rules above.

    Raises:
        UsageError: If the path is refused or cannot be opened, naming it and the reason.
    """
    check_output(path, what=what, force=force, make_parents=make_parents)
    flags = os.O_WRONLY | os.O_CREAT | getattr(os, "O_CLOEXEC", 0)
    flags |= os.O_TRUNC if force else os.O_EXCL
    try:
        fd = os.open(path, flags, 0o666)
    except FileExistsError:
        raise UsageError(f"{path}: already exists; pass --force to overwrite it") from None
    except OSError as error:
        raise cannot_write(path, error, what) from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):  # replaced by something else since the check
        os.close(fd)
        raise UsageError(f"{path}: not a regular file; give a file name")
    return os.fdopen(fd, "wb", buffering=-1 if buffered else 0)


@contextmanager
def written(path: Path, *, what: str, force: bool, make_parents: bool = False) -> Iterator[BinaryIO]:
    """``open_output`` as a context: an ``OSError`` while writing is a UsageError naming ``path``.

    A file left half-written by such an error is removed.
    """
    stream = open_output(path, what=what, force=force, make_parents=make_parents)
    try:
        with stream:
            yield stream
    except OSError as error:
        path.unlink(missing_ok=True)
        raise cannot_write(path, error, what) from None


def default_log_path(program: Path, now: datetime) -> Path:
    """``logs/<program stem>-<UTC time>.mcap``, e.g. ``logs/peg-20261122T031500Z.mcap``.

    Args:
        program: Path of the program file.
        now: Time of the run; a naive datetime is taken as UTC.
    """
    utc = now.replace(tzinfo=UTC) if now.tzinfo is None else now.astimezone(UTC)
    return Path("logs") / f"{program.stem}-{utc:%Y%m%dT%H%M%SZ}.mcap"


def claim_log_path(program: Path, now: datetime) -> Path:
    """:func:`default_log_path`, or with ``-2``, ``-3``, ... before ``.mcap``: created empty, for one run.

    The file is created with ``O_EXCL`` (and ``logs/`` if missing), so runs started in the same
    second, in one process or several, each get a log of their own; the run then writes it.

    Raises:
        UsageError: If ``logs/`` or the file cannot be created, naming the path and the reason.
    """
    first = default_log_path(program, now)
    path, number = first, 1
    try:
        first.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise cannot_write(first, error, "the log") from None
    while True:
        try:
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666))
            return path
        except FileExistsError:
            number += 1
            path = first.with_name(f"{first.stem}-{number}.mcap")
        except OSError as error:
            raise cannot_write(path, error, "the log") from None
