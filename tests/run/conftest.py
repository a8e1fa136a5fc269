"""Shared runs of the ``cosmos run`` acceptance tests.

The shipped programs (``programs/*.cos``) run once each through the command
line, in a background thread started with the first test of this directory;
their logs serve both the "every shipped program runs" test and the tests that
judge a particular program (``comply_slope.cos``, ``contact_slide.cos``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import pytest
from run_support import PROGRAMS, SHIPPED, BackgroundRuns, ProgramRun


@pytest.fixture(scope="session")
def background_runs(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[BackgroundRuns]:
    """The queue of CLI runs; the shipped programs are queued at once if any test needs them."""
    runs = BackgroundRuns(tmp_path_factory.mktemp("shipped"))
    if any("shipped_run" in getattr(item, "fixturenames", ()) for item in request.session.items):
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
        return background_runs.result(name)

    return get
