"""An interrupted sweep (Ctrl-C, then kill -9) goes on where it stopped: no run repeated or lost."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import psutil
import pytest
from sweep_support import TABLE_Z, TOUCH_TABLE

import cosmos
from cosmos.sweep.tap import summarize
from tests.cli_in_process import cosmos_in_process as cosmos_cli

RUNS = 7


def sweep_command(out: Path, *options: str) -> list[str]:
    return [
        sys.executable, "-m", "cosmos", "sweep", str(TOUCH_TABLE), "--runs", str(RUNS), "--seed", "5",
        "--vary", TABLE_Z, "--workers", "1", "--out", str(out), *options,
    ]  # fmt: skip


def result_lines(results: Path) -> list[str]:
    if not results.exists():
        return []
    return [line for line in results.read_text().split("\n")[1:] if line]


def start_and_stop(out: Path, after: int, how: signal.Signals) -> subprocess.CompletedProcess[str] | None:
    """Start the sweep in its own process group; once ``after`` results are on disk, signal the group."""
    process = subprocess.Popen(
        sweep_command(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
    )
    results = out / "results.jsonl"
    deadline = time.monotonic() + 90
    while len(result_lines(results)) < after and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert process.poll() is None, "the sweep ended before it could be interrupted"
    if how is signal.SIGKILL:  # the sweep alone, as the kernel's OOM killer would: its workers must end
        workers = psutil.Process(process.pid).children(recursive=True)
        assert workers
        os.kill(process.pid, how)
        process.communicate(timeout=60)
        _, alive = psutil.wait_procs(workers, timeout=20)
        for orphan in alive:
            orphan.kill()
        assert not alive, "pool workers outlived their killed sweep"
        return None
    os.killpg(process.pid, how)  # as a terminal's Ctrl-C does: the whole group
    stdout, stderr = process.communicate(timeout=60)
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)


def test_interrupted_and_killed_sweep_resumes_without_repeating_or_losing_runs(tmp_path: Path) -> None:
    """Catches results lost on Ctrl-C or kill -9, runs started after Ctrl-C (the pool's queue had
    taken them: 2 runs done at Ctrl-C became 5), pool workers left running after kill -9, runs
    made twice on resuming, a cut last line that breaks the results file; then a --json object
    without the documented keys, a kept log that replay cannot read, a run that --sample does not
    make again (values drawn otherwise, or the variation not applied)."""
    out = tmp_path / "sweep"
    results = out / "results.jsonl"
    interrupted = start_and_stop(out, 2, signal.SIGINT)
    assert interrupted is not None
    assert interrupted.returncode == 130, interrupted.stderr
    assert "Traceback" not in interrupted.stderr
    assert "interrupted:" in interrupted.stderr
    after_sigint = result_lines(results)
    assert 2 <= len(after_sigint) <= 3  # the one worker's run under way finishes; none is started

    start_and_stop(out, len(after_sigint) + 1, signal.SIGKILL)
    after_sigkill = result_lines(results)
    assert after_sigkill[: len(after_sigint)] == after_sigint
    assert len(after_sigkill) > len(after_sigint)

    plot = tmp_path / "success.png"
    finished = subprocess.run(
        sweep_command(out, "--json", "--plot", str(plot)), capture_output=True, text=True, timeout=120
    )
    assert finished.returncode == 0, finished.stderr
    final = result_lines(results)
    assert final[: len(after_sigkill)] == after_sigkill  # nothing done before is rewritten
    runs = [json.loads(line) for line in final]
    assert sorted(r["index"] for r in runs) == list(range(RUNS))  # each run once: none lost, none twice
    first_workers = {json.loads(line)["worker"] for line in after_sigkill}
    resumed = [r for r in runs if r["worker"] not in first_workers]
    assert len(resumed) == RUNS - len(after_sigkill)  # the last invocation made only the missing runs
    check_report(json.loads(finished.stdout), runs, plot)


def check_report(report: dict, runs: list[dict], plot: Path) -> None:
    """The --json object, a kept log that replay reads, and a failed run made again alone by --sample."""
    assert report["runs"] == RUNS and report["succeeded"] == sum(r["ok"] for r in runs)
    assert report["success_rate"] == report["succeeded"] / RUNS
    low, high = report["ci95"]
    assert 0 <= low <= report["success_rate"] <= high <= 1
    assert sorted(report["results"], key=lambda r: r["index"]) == sorted(runs, key=lambda r: r["index"])
    for result in report["results"]:
        assert {"index", "ok", "outcome", "line", "reason", "values"} <= set(result)
        assert set(result["values"]) == {"table.z", "seed"}
    assert plot.stat().st_size > 1000
    failed = [r for r in runs if not r["ok"] and "log" in r]  # --keep failed (the default)
    assert failed, "seed 5 should give failed runs for this test to bite"
    replay = cosmos_cli("replay", failed[0]["log"])
    assert replay.returncode == 0, replay.stderr

    log = Path(failed[0]["log"]).with_name("again.mcap")
    results = Path(failed[0]["log"]).parent.parent / "results.jsonl"
    sample = f"{results}:{failed[0]['index']}"
    again = cosmos_cli("run", str(TOUCH_TABLE), "--sample", sample, "--log", str(log))
    assert again.returncode == 1, again.stderr
    run = cosmos.load(log)
    state = run.record.state
    alone = summarize(run.events, state.t, state.line, np.linalg.norm(state.wrench[:, :3], axis=1))
    for key in ("ok", "outcome", "line", "statement", "reason"):
        assert alone[key] == failed[0][key]
    assert alone["duration_s"] == pytest.approx(failed[0]["duration_s"], abs=1e-9)
    assert alone["peak_force_n"] == pytest.approx(failed[0]["peak_force_n"], abs=1e-5)
