"""``cosmos repl``: an interactive session on a live simulated arm, logged like a run."""

from __future__ import annotations

import sys
from datetime import UTC, datetime
from pathlib import Path

from cosmos.repl.app import ReplApp
from cosmos.runlog.writer import default_log_path

DEFAULT_PROGRAM = Path("repl.cos")
"""Names the default log: ``logs/repl-<UTC time>.mcap``."""


def run_repl(log_path: Path | None) -> int:
    """Run a REPL session on the terminal (or on lines piped to stdin); return the exit status.

    Raises:
        UsageError: The log cannot be created.
    """
    log_path = log_path or default_log_path(DEFAULT_PROGRAM, datetime.now(UTC))
    return ReplApp(log_path, sys.stdout).run()
