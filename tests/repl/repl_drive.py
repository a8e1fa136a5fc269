"""Driving a REPL session through prompt_toolkit's pipe input, as a person types."""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from prompt_toolkit.history import InMemoryHistory
from prompt_toolkit.input import create_pipe_input
from prompt_toolkit.output import DummyOutput

from cosmos.repl.app import ReplApp
from cosmos.robots import DEFAULT_ROBOT, Robot
from cosmos.runlog.reader import RunRecord, read_log

ENTER = "\r"
CTRL_C = "\x03"
CTRL_D = "\x04"


@dataclass
class Driven:
    """A finished session: the app (its arm still readable), what it printed, its log."""

    app: ReplApp
    status: int
    output: str
    log: RunRecord

    @property
    def tool_position(self) -> np.ndarray:
        """Tool point [m], world, as the session's runtime senses it now."""
        return np.array(self.app.engine.session.runtime.evaluation.position)

    def done_time(self, statement: str) -> float:
        """Simulated time of the ``done`` event of the first statement with this text [s]."""
        return next(e.t for e in self.log.events if e.kind == "done" and e.statement == statement)

    def position_at(self, t_s: float) -> np.ndarray:
        """Tool point [m] of the last logged state sample at or before ``t_s``."""
        index = max(int(np.searchsorted(self.log.state.t, t_s + 1e-9, side="right")) - 1, 0)
        return np.array(self.log.state.x[index])


def drive(tmp_path: Path, keys: str, app_hook=None, robot: Robot = DEFAULT_ROBOT) -> Driven:  # noqa: ANN001
    """Type ``keys`` into a fresh session (end them with Ctrl-D) and run it to the end.

    Args:
        tmp_path: Where the log goes.
        keys: What is typed, Enter as ``\\r``.
        app_hook: Called with the app before it runs (e.g. to start a timer).
    """
    stream = io.StringIO()
    with create_pipe_input() as pipe:
        pipe.send_text(keys)
        app = ReplApp(
            tmp_path / "session.mcap",
            stream,
            input=pipe,
            output=DummyOutput(),
            history=InMemoryHistory(),
            robot=robot,
        )
        if app_hook is not None:
            app_hook(app)
        status = app.run()
    return Driven(app, status, stream.getvalue(), read_log(app.log_path))
