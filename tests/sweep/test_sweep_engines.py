"""The local pool and a Dask cluster make the same runs, result for result."""

from __future__ import annotations

from typing import Any

import pytest
from sweep_support import TABLE_Z, TOUCH_TABLE

from cosmos.sweep.engines import LocalPool
from cosmos.sweep.parameters import parse_varies
from cosmos.sweep.results import Keep, SweepSpec
from cosmos.sweep.worker import TIMING_FIELDS

RUNS = 4


def collect(engine: Any, tasks: list) -> dict[int, dict[str, Any]]:
    results: dict[int, dict[str, Any]] = {}

    def keep(result: dict[str, Any]) -> None:
        assert result["index"] not in results, "a run reported twice"
        results[result["index"]] = result

    engine.run(tasks, keep)
    return results


def without_timing(result: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in result.items() if k not in TIMING_FIELDS}


def test_dask_local_cluster_gives_the_local_pool_s_results_run_by_run() -> None:
    """Catches results that depend on the process or machine a run lands on (state kept between runs,
    draws made in the worker), and a pool that starts a process per run."""
    distributed = pytest.importorskip("distributed")
    from cosmos.sweep.engines import DaskCluster

    spec = SweepSpec(str(TOUCH_TABLE), TOUCH_TABLE.read_text(), 5, parse_varies([TABLE_Z]))
    tasks = [spec.task(i, Keep.NONE) for i in range(RUNS)]
    pooled = collect(LocalPool(2), tasks)
    assert sorted(pooled) == list(range(RUNS))
    assert len({r["worker"] for r in pooled.values()}) <= 2  # workers make many runs each
    with (
        distributed.LocalCluster(
            n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        clustered = collect(DaskCluster(client), tasks)
    assert sorted(clustered) == list(range(RUNS))
    for index in range(RUNS):
        assert without_timing(clustered[index]) == without_timing(pooled[index])
    outcomes = {r["ok"] for r in pooled.values()}
    assert outcomes == {True, False}, "the runs should both succeed and fail for the comparison to bite"
