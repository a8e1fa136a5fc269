"""The read-run loop and what Ctrl-C does in it.

At the prompt, Ctrl-C clears the line (prompt_toolkit raises KeyboardInterrupt,
the loop asks again). While an input runs, SIGINT is caught by a handler that
asks the executor to stop: the statement ends, the arm holds its pose, and the
prompt comes back. No user mistake ends the session; a bug in cosmos is
reported in one line (the traceback with ``COSMOS_DEBUG=1``) and the arm is
asked to hold.
"""

from __future__ import annotations

import os
import signal
import threading
import traceback
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

from cosmos.errors import CosmosError
from cosmos.repl.commands import bare_command, command_hint, is_command, run_command
from cosmos.repl.engine import ReplEngine
from cosmos.repl.output import Tone
from cosmos.repl.reader import Reader

DEBUG_ENV = "COSMOS_DEBUG"
"""Set to show the traceback of an internal error."""


@contextmanager
def ctrl_c_stops_arm(engine: ReplEngine) -> Iterator[None]:
    """While inside, SIGINT asks the running statement to stop and hold (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def request_stop(signum: int, frame: FrameType | None) -> None:
        engine.interrupt()

    previous = signal.signal(signal.SIGINT, request_stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def handle_input(engine: ReplEngine, text: str) -> bool:
    """Run one input (statements or a ``:command``); False when the session should end."""
    printer = engine.printer
    try:
        with ctrl_c_stops_arm(engine):
            if is_command(text):
                return run_command(engine, text)
            if (word := bare_command(text)) and word not in engine.state.procedures:
                return run_command(engine, f":{word}")  # help, exit, quit: as typed elsewhere
            if not engine.submit(text) and command_hint(text):
                printer.write(command_hint(text), Tone.NOTE)
            return True
    except CosmosError as error:
        printer.write(error.render(), Tone.ERROR)
    except KeyboardInterrupt:
        printer.write("interrupted", Tone.ERROR)
        _hold(engine)
    except Exception as error:  # noqa: BLE001 - a bug must not end the session or lose the log
        printer.write(f"internal error (a bug in cosmos): {type(error).__name__}: {error}", Tone.ERROR)
        if os.environ.get(DEBUG_ENV):
            printer.write(traceback.format_exc(), Tone.NOTE)
        _hold(engine)
    return True


def _hold(engine: ReplEngine) -> None:
    try:
        engine.executor.hold()
    except Exception as error:  # noqa: BLE001 - best effort after a failure
        engine.printer.write(f"could not hold the arm: {error}", Tone.ERROR)


def run_loop(engine: ReplEngine, read: Reader) -> None:
    """Read and run inputs until Ctrl-D or ``:quit``."""
    while True:
        try:
            text = read()
        except KeyboardInterrupt:
            continue
        except EOFError:
            return
        if not handle_input(engine, text):
            return
