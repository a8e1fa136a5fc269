"""What a user sees while kernels compile: at once what is compiled and why, then progress.

A first run on a machine compiles the kernels (numba, about half a minute of
CPU) before the arm moves; without a word it would look like a hang. numba
announces every compilation (``numba:compile`` events; a kernel loaded from the
cache is not compiled and says nothing): the first compilation of a group of
kernels prints one line naming the group and the expected time, later ones
print how far it has got every few seconds, and the process's end prints the
total. Lines go to stderr, whole lines only, so they read the same in a log and
print above a terminal's status line.
"""

from __future__ import annotations

import atexit
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

from numba.core import event

PROGRESS_EVERY_S = 5.0
"""Seconds between two progress lines while kernels compile."""


@dataclass(frozen=True)
class KernelGroup:
    """Kernels compiled together for one part of cosmos, and about how long that takes on one core."""

    prefix: str
    name: str
    estimate_s: float


GROUPS = (
    KernelGroup("cosmos.obstacles.", "the obstacle field", 5.0),
    KernelGroup("cosmos.runlog.", "the run log's writer", 2.0),
    KernelGroup("cosmos.", "the controller", 15.0),
)
"""Measured on the development machine with a fresh cache (``cosmos bench`` reports the total)."""


def group_of(module: str) -> KernelGroup | None:
    """The group a kernel of ``module`` belongs to (None for code outside cosmos)."""
    return next((group for group in GROUPS if module.startswith(group.prefix)), None)


def say(text: str) -> None:
    """One line on stderr (the stream in use now, so redirections and captures see it)."""
    print(f"cosmos: {text}", file=sys.stderr, flush=True)


class CompileNotice(event.Listener):
    """Announces kernel compilations on stderr (a numba event listener)."""

    def __init__(self, where: str, summary_at_exit: bool = True) -> None:
        self.where = where
        self.summary_at_exit = summary_at_exit
        self.announced: set[str] = set()
        self.compiled = 0
        self.started = 0.0
        self.reported = 0.0
        self.depth = 0
        self.top_started = 0.0
        self.seconds = 0.0
        self.on_first_compile: Callable[[], None] | None = None
        """Called once, when this process first compiles (a first run: helpers can start)."""

    def on_start(self, ev: event.Event) -> None:
        """A kernel starts compiling: name its group the first time."""
        self.depth += 1
        if self.depth == 1:
            self.top_started = time.perf_counter()
        group = group_of(ev.data["dispatcher"].py_func.__module__)
        if group is None or group.name in self.announced:
            return
        if not self.announced and self.on_first_compile is not None:
            self.on_first_compile()
        if not self.announced:
            self.started = self.reported = time.perf_counter()
            if self.summary_at_exit:
                atexit.register(self.summary)
        self.announced.add(group.name)
        say(
            f"compiling {group.name} for this machine, once: about {group.estimate_s:.0f} s "
            f"(kept in {self.where})"
        )

    def on_end(self, ev: event.Event) -> None:
        """A kernel is compiled: count it; every few seconds, say how far compiling has got."""
        self.depth -= 1
        if self.depth == 0:
            self.seconds += time.perf_counter() - self.top_started
        if group_of(ev.data["dispatcher"].py_func.__module__) is None:
            return
        self.compiled += 1
        now = time.perf_counter()
        if self.depth == 0 and now - self.reported >= PROGRESS_EVERY_S:
            self.reported = now
            say(f"  {self.compiled} kernels compiled ({self.seconds:.0f} s)")

    def summary(self) -> None:
        """At the process's end: how many kernels were compiled, in how long."""
        if self.compiled:
            kernels = "kernel" if self.compiled == 1 else "kernels"
            say(f"compiled {self.compiled} {kernels} in {self.seconds:.0f} s; later runs load them")


def install(where: str) -> CompileNotice:
    """Listen to numba's compilations from now on; ``where`` names the cache in the first line."""
    notice = CompileNotice(where)
    event.register("numba:compile", notice)
    return notice
