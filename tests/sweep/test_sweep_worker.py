"""One run in a worker: what the tap keeps equals what the run's log says."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from sweep_support import TOUCH_TABLE

import cosmos
from cosmos.sweep.tap import summarize
from cosmos.sweep.variation import WorkcellVariation
from cosmos.sweep.worker import RunTask, run_task


@pytest.mark.parametrize("table_z", [0.0, -0.05])
def test_tap_summary_equals_the_summary_of_the_run_s_log(tmp_path: Path, table_z: float) -> None:
    """Catches the tap missing an event or a sample, or an outcome that differs from cosmos.load's."""
    source = TOUCH_TABLE.read_text()
    task = RunTask(0, str(TOUCH_TABLE), source, {"table.z": table_z, "seed": 3.0}, keep_log=True)
    result = run_task(task)
    log = tmp_path / "run.mcap"
    log.write_bytes(result["log_bytes"])
    run = cosmos.load(log)
    state = run.record.state
    from_log = summarize(run.events, state.t, state.line, np.linalg.norm(state.wrench[:, :3], axis=1))
    assert result["ok"] == run.ok == from_log["ok"] == (table_z == 0.0)
    if not run.ok:
        assert run.outcome is not None and run.outcome.span is not None
        assert (result["outcome"], result["line"], result["reason"]) == (
            run.outcome.kind.value,
            run.outcome.span.line,
            run.outcome.reason,
        )
        assert result["statement"] == "CONTACT DOWN"
    assert result["duration_s"] == pytest.approx(run.duration_s, abs=1e-9)
    assert [(s["line"], s["statement"]) for s in result["statements"]] == [
        (s["line"], s["statement"]) for s in from_log["statements"]
    ]
    for tapped, logged in zip(result["statements"], from_log["statements"], strict=True):
        assert tapped["duration_s"] == pytest.approx(logged["duration_s"], abs=1e-9)
        assert tapped["peak_force_n"] == pytest.approx(logged["peak_force_n"], abs=1e-5)  # log: 1e-6 N
    # The log says how the workcell varied, as cosmos run arguments.
    assert run.record.metadata["variation"] == WorkcellVariation.from_values(task.values).arguments()
    assert ("table.z=" in run.record.metadata["variation"]) == (table_z != 0.0)
    assert result["overhead_s"] + result["simulate_s"] == pytest.approx(result["wall_s"])


def test_a_failure_a_try_takes_over_is_not_the_run_s_failure(tmp_path: Path) -> None:
    """Catches the tap counting the first failed event as the run's failure: a TRY's ON FAIL
    took it over and the run succeeded (cosmos run exits 0), yet every sweep run of the shipped
    touch_and_recover.cos was counted failed ("line 17 INSERT DOWN: jammed", 0 of 6)."""
    source = "TRY\n  MOVE BY (0, 0, 10 mm) UNTIL FORCE > 50 N TIMEOUT 0.05 s\nON FAIL\n  WAIT 0.1 s\nEND\n"
    task = RunTask(0, "recover.cos", source, {"seed": 1.0}, keep_log=True)
    result = run_task(task)
    log = tmp_path / "run.mcap"
    log.write_bytes(result["log_bytes"])
    run = cosmos.load(log)
    assert [e.kind for e in run.events if e.kind in ("failed", "recovery")] == ["failed", "recovery"]
    assert run.ok and result["ok"] and result["outcome"] == "ok" and result["line"] is None


def test_tap_reads_an_interrupted_run_as_cosmos_load_does(tmp_path: Path) -> None:
    """Catches the tap missing the executor's interruption event (a stopped run counted a success)."""
    from cosmos.execution.session import Session
    from cosmos.lang import compile_program
    from cosmos.runtime.rates import Rates
    from cosmos.sweep.tap import LogTap
    from cosmos.workcell import fixture_frames

    source = "MOVE BY (0, 0, 50 mm)\nMOVE BY (0, 0, -50 mm)\n"
    plan = compile_program(source, "stop.cos", fixture_frames())
    calls = []

    def stop_on_second_call(progress: object) -> None:
        calls.append(progress)
        if len(calls) == 2:
            session.executor.stop_requested = True

    log = tmp_path / "stop.mcap"
    with Session("stop.cos", source, log, Rates(), progress=stop_on_second_call) as session:
        tap = LogTap(session.log)
        with pytest.raises(cosmos.CosmosError):
            session.executor.run(plan)
    tapped, run = tap.summary(), cosmos.load(log)
    assert run.outcome is not None and run.outcome.kind is cosmos.OutcomeKind.INTERRUPTED
    assert run.outcome.span is not None
    assert (tapped["ok"], tapped["outcome"], tapped["line"], tapped["reason"]) == (
        False,
        "interrupted",
        run.outcome.span.line,
        run.outcome.reason,
    )
