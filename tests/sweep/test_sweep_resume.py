"""An interrupted sweep (Ctrl-C, then kill -9) goes on where it stopped: no run repeated or lost."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from sweep_support import TABLE_Z, TOUCH_TABLE

RUNS = 7


def sweep_command(out: Path) -> list[str]:
    return [
        sys.executable, "-m", "cosmos", "sweep", str(TOUCH_TABLE), "--runs", str(RUNS), "--seed", "2",
        "--vary", TABLE_Z, "--workers", "1", "--out", str(out), "--keep", "none",
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
    os.killpg(process.pid, how)  # as a terminal's Ctrl-C does: the whole group
    stdout, stderr = process.communicate(timeout=60)
    if how is signal.SIGKILL:
        return None
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)


def test_interrupted_and_killed_sweep_resumes_without_repeating_or_losing_runs(tmp_path: Path) -> None:
    """Catches results lost on Ctrl-C or kill -9, runs made twice on resuming, or a cut last line
    that breaks the results file."""
    out = tmp_path / "sweep"
    results = out / "results.jsonl"
    interrupted = start_and_stop(out, 2, signal.SIGINT)
    assert interrupted is not None
    assert interrupted.returncode == 130, interrupted.stderr
    assert "Traceback" not in interrupted.stderr
    assert "interrupted:" in interrupted.stderr
    after_sigint = result_lines(results)
    assert len(after_sigint) >= 2

    start_and_stop(out, len(after_sigint) + 1, signal.SIGKILL)
    after_sigkill = result_lines(results)
    assert after_sigkill[: len(after_sigint)] == after_sigint
    assert len(after_sigkill) > len(after_sigint)

    finished = subprocess.run(sweep_command(out), capture_output=True, text=True, timeout=120)
    assert finished.returncode == 0, finished.stderr
    final = result_lines(results)
    assert final[: len(after_sigkill)] == after_sigkill  # nothing done before is rewritten
    runs = [json.loads(line) for line in final]
    assert sorted(r["index"] for r in runs) == list(range(RUNS))  # each run once: none lost, none twice
    first_workers = {json.loads(line)["worker"] for line in after_sigkill}
    resumed = [r for r in runs if r["worker"] not in first_workers]
    assert len(resumed) == RUNS - len(after_sigkill)  # the last invocation made only the missing runs
