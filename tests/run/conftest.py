"""Shared runs of the ``cosmos run`` acceptance tests.

The shipped programs (``programs/*.cos``) run once each through the command
line; their logs serve both the "every shipped program runs" test and the tests
that judge a particular program (``comply_slope.cos``, ``contact_slide.cos``).
In a single process the runs start in a background thread with the first test of
this directory, so the second core works through them meanwhile. Under
pytest-xdist (the README's command: two workers, each its own process) the other
worker keeps the second core busy, and each worker runs a program when one of its
tests first asks for it: only the workers whose files need a program run it.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator

import pytest
from run_support import PROGRAMS, SHIPPED, BackgroundRuns, ProgramRun


def _in_an_xdist_worker() -> bool:
    return "PYTEST_XDIST_WORKER" in os.environ


@pytest.fixture(scope="session")
def background_runs(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[BackgroundRuns]:
    """The queue of CLI runs; in one process, the shipped programs are queued at once if any test
    needs them (a worker of xdist collects every test but runs only its share: it queues them as
    they are asked for)."""
    runs = BackgroundRuns(tmp_path_factory.mktemp("shipped"))
    wanted = any("shipped_run" in getattr(item, "fixturenames", ()) for item in request.session.items)
    if wanted and not _in_an_xdist_worker():
        # The one judged on its own first, then the rest in name order.
        for name in sorted(SHIPPED, key=lambda n: (n != "comply_slope.cos", n)):
            runs.submit(name, PROGRAMS / name)
    yield runs
    runs.close()


@pytest.fixture(autouse=True)
def _start_background(background_runs: BackgroundRuns) -> None:
    """Start the shipped runs with the first test of this directory, whichever it is."""


@pytest.fixture(scope="session")
def shipped_run(background_runs: BackgroundRuns) -> Callable[[str], ProgramRun]:
    """A function: the finished CLI run of a shipped program, by file name."""

    def get(name: str) -> ProgramRun:
        background_runs.submit(name, PROGRAMS / name)  # ignored when it is queued already
        return background_runs.result(name)

    return get
