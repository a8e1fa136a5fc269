"""A whole REPL session: open the arm and its log, read and run inputs, close the log.

:class:`ReplApp` is what ``cosmos repl`` runs, and what the tests drive through
prompt_toolkit's pipe input.
"""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import FrameType
from typing import TextIO

from prompt_toolkit.history import History
from prompt_toolkit.input import Input
from prompt_toolkit.output import Output

from cosmos import __version__
from cosmos.errors import UsageError
from cosmos.execution.session import Session
from cosmos.hand.tool import Tool
from cosmos.hand.work_object import SHIPPED_OBJECTS
from cosmos.repl.engine import ReplEngine
from cosmos.repl.loop import run_loop
from cosmos.repl.output import Printer, Tone
from cosmos.repl.reader import Reader, history_path, open_history, plain_reader, prompt_reader
from cosmos.repl.statements import REPL_FILE
from cosmos.robots import DEFAULT_ROBOT, Robot
from cosmos.runtime.rates import Rates

BANNER = "cosmos {version}: a simulated {arm} in its workcell. :help for help, Ctrl-D to leave."


class ReplApp:
    """One interactive session on a live simulated arm, logged like a run.

    Args:
        log_path: Where the MCAP log goes.
        stream: Where messages go (the terminal's stdout).
        input: Keyboard input for the prompt; None: the terminal, or plain lines
            from ``stdin`` when it is not a terminal.
        output: Screen output for the prompt (None: the terminal).
        history: Input history; None: the file of :func:`history_path`.
        stdin: Read when there is no terminal (None: ``sys.stdin``).
        robot: The arm.
        tool: The hand, for the whole session (``--tool``): the gripper's workcell has its
            peg and blocks.

    Raises:
        UsageError: The log file cannot be created.
    """

    def __init__(
        self,
        log_path: Path,
        stream: TextIO,
        input: Input | None = None,
        output: Output | None = None,
        history: History | None = None,
        stdin: TextIO | None = None,
        robot: Robot = DEFAULT_ROBOT,
        tool: Tool = Tool.PEG,
    ):
        interactive = input is not None or _is_terminal(stdin or sys.stdin)
        self.printer = Printer(stream, color=interactive and _is_terminal(stream))
        if interactive:  # numba compiles the controller's kernels on first use, then caches them
            self.printer.write(
                "starting the arm (a first run compiles the controller: up to a minute)", Tone.NOTE
            )
        try:
            objects = SHIPPED_OBJECTS if tool is Tool.GRIPPER else ()
            session = Session(REPL_FILE, None, log_path, Rates(), robot=robot, tool=tool, objects=objects)
        except OSError as error:
            raise UsageError(f"cannot write the log {log_path}: {error.strerror or error}") from None
        self.engine = ReplEngine(session, self.printer, show_progress=input is None and interactive)
        self.read: Reader
        if interactive:
            self.read = prompt_reader(
                self.engine, history or open_history(history_path(), self.printer), input, output
            )
        else:
            self.read = plain_reader(stdin or sys.stdin, self.printer)

    @property
    def log_path(self) -> Path:
        """The session's log."""
        return self.engine.session.log_path

    def run(self) -> int:
        """Greet, read and run inputs until Ctrl-D or ``:quit``, then close the log.

        SIGTERM or SIGHUP (the terminal closed) end the session the same way, the
        log closed and complete.

        Returns:
            0, or 1 when the session was ended by a signal.
        """
        self.printer.write(BANNER.format(version=__version__, arm=self.engine.session.robot.title))
        self.printer.write(f"log: {self.log_path}", Tone.NOTE)
        status = 0
        try:
            with _signals_end_session():
                run_loop(self.engine, self.read)
        except SessionEnded as ended:
            self.printer.write(f"session ended by {ended}", Tone.ERROR)
            status = 1
        finally:
            self.close()
        self.printer.write(f"log: {self.log_path}")
        return status

    def close(self) -> None:
        """Attach the transcript to the log as the session's program, and close the log."""
        log = self.engine.session.log
        if not log.closed:
            log.attach_source(self.engine.transcript.text())
        self.engine.session.close()


class SessionEnded(BaseException):
    """A signal ended the session (a BaseException, so no ``except Exception`` keeps it going)."""


@contextmanager
def _signals_end_session() -> Iterator[None]:
    """While inside, SIGTERM and SIGHUP raise :class:`SessionEnded` (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def end(signum: int, frame: FrameType | None) -> None:
        raise SessionEnded(signal.Signals(signum).name)

    signals = [signal.SIGTERM] + ([signal.SIGHUP] if hasattr(signal, "SIGHUP") else [])
    previous = {sig: signal.signal(sig, end) for sig in signals}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _is_terminal(stream: TextIO) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False
