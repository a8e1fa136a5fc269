"""Set-up shared by the whole suite, before any test module imports MuJoCo."""

import os
import sys

import pytest

# MuJoCo picks its OpenGL backend once, at its first import; without a display its default
# (GLFW) cannot render, and the tests that write a video (``cosmos replay --video``) failed
# whenever a test module imported MuJoCo before the replay could choose EGL itself
# (cosmos.replay.playback.prefer_headless_gl). The README's test command sets nothing.
os.environ.setdefault("MUJOCO_GL", "egl")

# Bytecode kept, as an install keeps it (cosmos.bench.programs.user_environment): with
# PYTHONDONTWRITEBYTECODE set (some development machines) each of pytest-xdist's workers
# rewrote and compiled every test module again (3-4 s of CPU a worker), and every
# ``python -m cosmos`` the tests start compiled the modules it imports again. Set here, before
# the test modules are imported and the workers started.
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

SIMULATING_FIRST = ("hand", "run", "sweep")
"""The directories of tests/ whose files run the simulated arm longest, in the order they are
handed to pytest-xdist's workers (the README's command runs two, a file at a time): long files
first, so that no worker is still in a long file when the other has nothing left to run."""


def _file_rank(item: pytest.Item) -> int:
    tests = item.config.rootpath / "tests"
    parts = item.path.relative_to(tests).parts if item.path.is_relative_to(tests) else ()
    if len(parts) > 1 and parts[0] in SIMULATING_FIRST:
        return SIMULATING_FIRST.index(parts[0])
    return len(SIMULATING_FIRST)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The simulating directories' files first (a stable sort: each file's tests keep their
    order and stay together, as ``--dist loadfile`` needs)."""
    items.sort(key=_file_rank)
