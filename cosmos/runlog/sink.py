"""The file the Rust MCAP writer writes through, so that its I/O errors reach Python as one line.

Foxglove's writer, given a path, reports a failed write as ``RuntimeError:
FoxgloveError: MCAP error: I/O error``, prints a line to stderr for every
message after it, and, if it is still open when the interpreter shuts down,
ends in a Rust panic. Given this file object instead, every write goes through
:meth:`LogSink.write`: the first ``OSError`` is kept and later writes are
dropped (the position moves on as if they were written: the writer checks it),
so the writer never sees an error; :meth:`LogSink.check` raises it as
a :class:`~cosmos.errors.UsageError` naming the path and the reason, at the
next flush or close of the log.
"""

from __future__ import annotations

import io
import os
import threading
import weakref
from pathlib import Path
from typing import Any, BinaryIO

from foxglove.mcap import MCAPWriter

from cosmos.runlog.output import cannot_write

SYNC_EVERY_S = 1.0
"""Wall time between the log's fsyncs while it is written [s]: what a power loss (or the
machine stopping) can lose of a run, beside the fsync's own time. A process killed in any
way (SIGKILL, a crash) loses nothing the writer has handed to the OS (the flushes:
:mod:`cosmos.runlog.writer`), so the fsyncs guard against the OS going down alone, which
needs no fsync per statement."""


class LogSink(io.RawIOBase):
    """An open output file that records its first write error instead of raising it.

    Args:
        path: The file's path, for the error message.
        stream: The file, opened unbuffered for writing.
        sync_every_s: Wall time between the fsyncs of the data :meth:`sync` was asked for [s].
    """

    def __init__(self, path: Path, stream: BinaryIO, sync_every_s: float = SYNC_EVERY_S):
        super().__init__()
        self.path = path
        self._stream = stream
        self.error: OSError | None = None
        self.reported = False  # whether check() has raised the error
        self._position = 0  # where the writer believes it is: the file's, until an error
        self._end = 0
        self.sync_every_s = sync_every_s
        # One fsync thread for the file's life, started by the first sync: a thread started
        # per statement cost the loop up to 2 ms each on a loaded machine (waiting for it to run).
        self._syncer: threading.Thread | None = None
        self._sync_state = threading.Condition()
        self._asked = 0  # syncs asked for
        self._synced = 0  # of them, those on disk (one fsync covers all asked before it began)
        self._closing = False
        self._now = False  # wait() wants the syncs asked for done now

    def writable(self) -> bool:
        """Yes."""
        return True

    def seekable(self) -> bool:
        """Yes (the writer goes back to fill in lengths)."""
        return True

    def write(self, data: bytes | bytearray | memoryview) -> int:  # type: ignore[override]
        """Write all of ``data`` (or nothing after an error); report it all written."""
        view = memoryview(data)
        size = view.nbytes
        if self.error is None:
            try:
                while view.nbytes:
                    written = self._stream.write(view)
                    view = view[written or 0 :]
            except OSError as error:
                self.error = error
        self._position += size
        self._end = max(self._end, self._position)
        return size

    def seek(self, offset: int, whence: int = io.SEEK_SET) -> int:
        """Move in the file (after an error, only the position the writer believes in)."""
        base = {io.SEEK_SET: 0, io.SEEK_CUR: self._position, io.SEEK_END: self._end}[whence]
        self._position = base + offset
        if self.error is None:
            try:
                self._stream.seek(self._position)
            except OSError as error:
                self.error = error
        return self._position

    def tell(self) -> int:
        """Position in the file."""
        return self._position

    def flush(self) -> None:
        """Nothing to do: the file is unbuffered (:meth:`sync` puts it on disk)."""

    def sync(self) -> None:
        """Ask the OS to put the data written so far on disk, beside the caller (who does not wait).

        The ``fsync`` runs in the file's sync thread, at most once every :attr:`sync_every_s`
        of wall time: it covers every sync asked for before it began, :meth:`wait` has the
        thread do it at once, and :meth:`close` waits for the last. Asking only counts (the
        thread is not woken): each wake-up of a thread from the loop's statement boundaries
        cost the loop the interpreter's lock twice (the thread's return from its wait and
        from ``fsync``), milliseconds a statement on a loaded machine. Its error is kept
        like a write error.
        """
        if self.error is not None:
            return
        with self._sync_state:
            self._asked += 1
            if self._syncer is None:
                self._syncer = threading.Thread(target=self._sync_loop, name="cosmos-log-fsync", daemon=True)
                self._syncer.start()

    def _sync_loop(self) -> None:
        state = self._sync_state
        while True:
            with state:
                state.wait_for(lambda: self._closing or self._now, timeout=self.sync_every_s)
                self._now = False
                if self._synced == self._asked:
                    if self._closing:  # nothing left
                        return
                    continue
                asked = self._asked
            try:
                os.fsync(self._stream.fileno())
            except (OSError, ValueError) as error:  # ValueError: closed under it (cannot happen: close waits)
                if self.error is None:
                    self.error = error if isinstance(error, OSError) else OSError(str(error))
            with state:
                self._synced = asked
                state.notify_all()

    def wait(self) -> None:
        """Wait until every :meth:`sync` asked for so far has put the data on disk."""
        with self._sync_state:
            self._now = True
            self._sync_state.notify_all()
            while self._synced < self._asked and self._syncer is not None and self._syncer.is_alive():
                self._sync_state.wait()
                if self._synced < self._asked:  # asked for during the fsync that ended
                    self._now = True
                    self._sync_state.notify_all()

    def _stop_syncing(self) -> None:
        """Wait for the last sync and end the sync thread."""
        with self._sync_state:
            self._closing = True
            self._sync_state.notify_all()
        if self._syncer is not None:
            self._syncer.join()

    def check(self) -> None:
        """Raise the first write error, if there was one.

        Raises:
            UsageError: Naming the path and the reason.
        """
        if self.error is not None:
            self.reported = True
            raise cannot_write(self.path, self.error, "the log")

    def close(self) -> None:
        """Close the file; an error closing it is kept like a write error."""
        if not self.closed:
            self._stop_syncing()
            try:
                self._stream.close()
            except OSError as error:
                if self.error is None:
                    self.error = error
        super().close()


def close_at_exit(log: weakref.ref[Any], writer: MCAPWriter, sink: LogSink) -> None:
    """Close a log left open (at exit or when collected), while Python can still run the sink."""
    try:
        still_open = log()
        if still_open is not None:
            still_open.close()  # at exit: the pending states too
        else:
            writer.close()
    except Exception:  # noqa: BLE001, S110 - nothing can be reported this late; the file stays readable
        pass
    sink.close()
