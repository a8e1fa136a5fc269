"""The user cache directory of cosmos (compiled kernels, the workcell's fixture frames).

``$COSMOS_CACHE_DIR`` if set, else the platform's user cache directory:
``$XDG_CACHE_HOME/cosmos`` or ``~/.cache/cosmos`` on Linux, ``~/Library/Caches/cosmos``
on macOS, ``%LOCALAPPDATA%/cosmos/Cache`` on Windows. Imports nothing heavy, so
commands that need no simulator (``cosmos check``) can use it.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

CACHE_ENV = "COSMOS_CACHE_DIR"
"""Environment variable naming the directory cosmos caches in (instead of the user cache)."""


def user_cache_root() -> Path:
    """``$COSMOS_CACHE_DIR``, else the platform's user cache directory for cosmos."""
    chosen = os.environ.get(CACHE_ENV)
    if chosen:
        return Path(chosen).expanduser()
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or str(Path.home() / "AppData" / "Local")
        return Path(base) / "cosmos" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "cosmos"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base).expanduser() / "cosmos"
