"""``cosmos repl``: an interactive session on a live simulated arm, logged like a run."""

from __future__ import annotations

import sys
from datetime import UTC, datetime
from pathlib import Path

from cosmos.hand.tool import Tool
from cosmos.repl.app import ReplApp
from cosmos.robots import DEFAULT_ROBOT, robot_named
from cosmos.runlog.output import check_output, claim_log_path

DEFAULT_PROGRAM = Path("repl.cos")
"""Names the default log: ``logs/repl-<UTC time>.mcap``."""


def run_repl(log_path: Path | None, force: bool = False, robot: str | None = None, tool: str = "peg") -> int:
    """Run a REPL session on the terminal (or on lines piped to stdin); return the exit status.

    The log follows ``cosmos run``'s rules (:mod:`cosmos.runlog.output`): an existing
    ``--log`` file is kept unless ``force``, and only the default ``logs/`` is created.

    Raises:
        UsageError: The log cannot be created.
    """
    if log_path is None:
        log_path = claim_log_path(DEFAULT_PROGRAM, datetime.now(UTC))
    else:
        check_output(log_path, what="the log", force=force)
    arm = robot_named(robot or DEFAULT_ROBOT.name)
    return ReplApp(log_path, sys.stdout, robot=arm, tool=Tool(tool.lower())).run()
