"""``cosmos sweep PROGRAM``: run a program many times in varied workcells and report its success rate."""

from __future__ import annotations

import hashlib
import json
import os
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

from cosmos.errors import UsageError
from cosmos.realism.plant_realism import IDEAL
from cosmos.sweep.parameters import parse_varies
from cosmos.sweep.results import RESULTS_NAME, Keep, ResultsFile, SweepSpec, log_name, results_list, sample
from cosmos.sweep.variation import WorkcellVariation, constant_variation

EXIT_INTERRUPTED = 130
"""Exit status of a sweep stopped by Ctrl-C (its finished runs are in the results file)."""


@dataclass(frozen=True)
class SweepOptions:
    """The options of ``cosmos sweep`` (documented in docs/sweep.md)."""

    program: Path
    runs: int
    seed: int
    vary: tuple[str, ...]
    workers: int | None
    cluster: str | None
    out: Path | None
    keep: Keep
    plot: Path | None
    as_json: bool
    ideal: bool = False


def default_out(program: Path, seed: int) -> Path:
    """Where a sweep's results go unless ``--out`` says: ``sweeps/<program>-seed<seed>``."""
    return Path("sweeps") / f"{program.stem}-seed{seed}"


def run_sweep(options: SweepOptions) -> int:
    """Run the sweep (resuming what its results file has), print the report; the exit status."""
    from cosmos.api import check
    from cosmos.sweep.engines import DaskCluster, LocalPool
    from cosmos.sweep.plot import plot_success
    from cosmos.sweep.report import render, summarize

    plan = check(options.program)  # a program that does not compile stops here, with its place
    for warning in plan.warnings:
        click.echo(warning.render(plan.source), err=True)
    varies = parse_varies(options.vary)
    spec = SweepSpec(str(options.program), plan.source, options.seed, varies, options.ideal)
    out = options.out or default_out(options.program, options.seed)
    results = ResultsFile(out / RESULTS_NAME, spec)
    todo = [spec.task(i, options.keep) for i in range(options.runs) if i not in results.done]
    done_before = len(results.done)
    engine = (
        DaskCluster(options.cluster) if options.cluster else LocalPool(options.workers or os.cpu_count() or 1)
    )
    progress = _Progress(options.runs, results.done) if sys.stderr.isatty() and not options.as_json else None

    def on_result(result: dict[str, Any]) -> None:
        log_bytes = result.pop("log_bytes", None)
        if log_bytes is not None:
            path = out / "logs" / log_name(result["index"])
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(log_bytes)
            result["log"] = str(path)
        results.add(result)
        if progress is not None:
            progress.advance(result)

    started = time.perf_counter()
    interrupted = False
    try:
        if progress is not None:
            with progress.bar:
                engine.run(todo, on_result)
        else:
            engine.run(todo, on_result)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        results.close()
    wall_s = time.perf_counter() - started
    done = results_list(results.done, options.runs)
    names = [vary.name for vary in varies]
    summary = summarize(done, names)
    if options.plot is not None and done:
        plot_success(done, names, options.plot)
    if options.as_json:
        click.echo(json.dumps(summary | {"results": list(done), "interrupted": interrupted}))
    else:
        for line in render(summary, str(options.program), str(results.path)):
            click.echo(line)
        where = (
            f"on the cluster {options.cluster}" if options.cluster else f"on {engine_workers(engine)} workers"
        )
        made = len(results.done) - done_before
        click.echo(f"this time: {made} runs made in {wall_s:.1f} s {where}")
    if interrupted:
        click.echo(
            f"interrupted: {len(done)} of {options.runs} runs done; the same command goes on from there",
            err=True,
        )
        return EXIT_INTERRUPTED
    return 0


def engine_workers(engine: object) -> int:
    """The number of local workers (0 for a cluster)."""
    return int(getattr(engine, "workers", 0))


class _Progress:
    """A progress bar on the terminal with the running success rate."""

    def __init__(self, total: int, done: dict[int, dict[str, Any]]) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        self.bar = Progress(
            TextColumn("{task.description}"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeRemainingColumn(),
            console=Console(stderr=True),
        )
        self.runs = len([i for i in done if i < total])
        self.succeeded = sum(1 for i, r in done.items() if i < total and r["ok"])
        self.task = self.bar.add_task(self._text(), total=total, completed=self.runs)

    def _text(self) -> str:
        rate = f"{100 * self.succeeded / self.runs:.0f} %" if self.runs else "-"
        return f"success {rate} ({self.succeeded}/{self.runs})"

    def advance(self, result: dict[str, Any]) -> None:
        """Count one more run."""
        self.runs += 1
        self.succeeded += bool(result["ok"])
        self.bar.update(self.task, advance=1, description=self._text())


def variation_for_run(
    program: Path, vary: Sequence[str], sample_text: str | None, seed: int, ideal: bool = False
) -> WorkcellVariation | None:
    """``cosmos run``'s varied workcell: ``--sample FILE:N`` (a sweep's run) or ``--vary`` constants.

    A sweep's run made on the ideal plant (its results' header says so) is made again on it.

    Raises:
        UsageError: Both given, a ``--vary`` that is a distribution, or a bad ``--sample``.
    """
    from cosmos.sweep.results import parse_sample

    if sample_text is not None:
        if vary:
            raise UsageError("--sample and --vary: give one (a sweep's run, or the values)")
        path, index = parse_sample(sample_text)
        header, values = sample(path, index)
        digest = hashlib.sha256(program.read_bytes()).hexdigest()
        if digest != header.get("source_sha256"):
            click.echo(
                f"{path}: the sweep ran another text of the program; running {program} as it is", err=True
            )
        return WorkcellVariation.from_values(values, ideal=ideal or header.get("plant") == IDEAL)
    return constant_variation(vary, seed, ideal) if vary else None
