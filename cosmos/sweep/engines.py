"""Where a sweep's runs are made: a local pool of worker processes, or a Dask cluster.

Both take the same :class:`~cosmos.sweep.worker.RunTask` values and run the same
:func:`~cosmos.sweep.worker.run_task`, so a run's result does not depend on where it ran.
Each reports results as runs end (:data:`OnResult`); on Ctrl-C it stops starting runs,
reports the ones under way as they finish, and raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, as_completed, wait
from itertools import islice
from typing import Any

from cosmos.errors import UsageError
from cosmos.sweep.worker import RunTask, run_task, warm_up

ORPHAN_CHECK_S = 0.5
"""How often a pool worker looks whether its parent is still there [s]."""

OnResult = Callable[[dict[str, Any]], None]

CLUSTER_MISSING = "--cluster needs Dask's distributed, an optional extra: pip install 'cosmos-osc[cluster]'"


def _start_worker() -> None:
    """A pool worker: Ctrl-C is the parent's to handle; it ends with its parent; load models once."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = os.getppid()
    threading.Thread(target=_exit_when_orphaned, args=(parent,), daemon=True).start()
    warm_up()


def _exit_when_orphaned(parent: int) -> None:
    """End this worker once its parent is gone (killed with -9, it cannot stop the pool)."""
    while os.getppid() == parent:
        time.sleep(ORPHAN_CHECK_S)
    os._exit(1)


class LocalPool:
    """``workers`` processes on this machine, each making many runs (no process start per run).

    Processes are spawned (not forked): each imports cosmos and loads the compiled kernels
    from numba's cache once, whatever state the parent is in.
    """

    def __init__(self, workers: int) -> None:
        if workers < 1:
            raise UsageError(f"--workers must be at least 1; got {workers}")
        self.workers = workers

    def run(self, tasks: Sequence[RunTask], on_result: OnResult) -> None:
        """Make every task's run; ``on_result`` with each result as it comes."""
        if not tasks:
            return
        context = multiprocessing.get_context("spawn")
        workers = min(self.workers, len(tasks))
        waiting = iter(tasks)
        with ProcessPoolExecutor(workers, mp_context=context, initializer=_start_worker) as pool:
            # One run per worker at a time: the pool hands submitted runs to its workers' queue at once,
            # where cancelling cannot reach them (Ctrl-C at 2 runs of 20 went on to make 7).
            under_way = {pool.submit(run_task, task) for task in islice(waiting, workers)}
            try:
                while under_way:
                    finished, _ = wait(under_way, return_when=FIRST_COMPLETED)
                    for future in finished:
                        on_result(future.result())
                        under_way.discard(future)
                        under_way.update(pool.submit(run_task, task) for task in islice(waiting, 1))
            except KeyboardInterrupt:
                for future in as_completed(under_way):  # the runs under way finish and are reported
                    if future.exception() is None:
                        on_result(future.result())
                raise


class DaskCluster:
    """The runs submitted to a Dask distributed scheduler (``--cluster ADDRESS``).

    Args:
        address: The scheduler's address (``tcp://host:8786``), or a ``distributed.Client``.
    """

    def __init__(self, address: Any) -> None:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise UsageError(CLUSTER_MISSING) from None
        self.address = address

    def run(self, tasks: Sequence[RunTask], on_result: OnResult) -> None:
        """Make every task's run on the cluster's workers; ``on_result`` with each as it comes."""
        from distributed import Client, as_completed

        if isinstance(self.address, Client):
            client, own = self.address, False
        else:
            try:
                client, own = Client(self.address, timeout="10s"), True
            except (OSError, TimeoutError, ValueError) as error:
                raise UsageError(f"--cluster {self.address}: cannot reach the scheduler: {error}") from None
        try:
            client.run(warm_up)  # the workers there now; one that joins later warms up on its first run
            futures = client.map(run_task, list(tasks), pure=False)
            try:
                for future in as_completed(futures):
                    on_result(future.result())
            except KeyboardInterrupt:
                client.cancel([f for f in futures if not f.done()])
                raise
        finally:
            if own:
                client.close()
