"""The ``cosmos`` command line: run, check, repl, replay, sweep, bench.

Exit status: 0 success; 1 the program failed (syntax, check or run-time
failure); 2 wrong usage. A user's mistake never shows a Python traceback.
"""

from __future__ import annotations

import sys
from contextlib import nullcontext
from pathlib import Path

import click

from cosmos import __version__
from cosmos.collector import collector_off
from cosmos.commands import (
    entry_points,
    process,
)  # before numpy's first import (cosmos.robots): one BLAS thread
from cosmos.errors import CosmosError, UsageError
from cosmos.robots import ROBOTS

process.forget_blas_threads()

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2


def _not_built(name: str) -> None:
    click.echo(f"cosmos {name}: not built yet", err=True)
    sys.exit(EXIT_USAGE)


def _finish(status: int) -> None:
    sys.exit(status)


def _report(error: CosmosError) -> None:
    click.echo(error.render(), err=True)
    sys.exit(EXIT_USAGE if isinstance(error, UsageError) else EXIT_FAILED)


_WHOLE_PROCESS: list[bool] = []
"""Set by :func:`main` called from the process's main module: this process is the command,
whose start-up objects stay frozen to the end (:func:`cosmos.collector.collector_off`)."""


# the program file is read (and refused if it is not one) by cosmos.lang.read_program
program_argument = click.argument("program", type=click.Path(path_type=Path, readable=False))


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="cosmos")
def cli() -> None:
    """COSMOS: operational-space task programs for a simulated PUMA 560 (or Franka Emika Panda)."""


@cli.command()
@program_argument
@click.option("--log", "log_path", type=click.Path(path_type=Path, readable=False), help="MCAP log path.")
@click.option("--servo-hz", type=click.FloatRange(min=1.0), default=None, help="Servo rate [Hz].")
@click.option(
    "--param-hz",
    type=click.FloatRange(min=1.0),
    default=None,
    help="Parameter-evaluation rate [Hz].",
)
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Seed of the wrist force/torque sensor's noise.",
)
@click.option("--force", is_flag=True, help="Overwrite the --log file if it exists.")
@click.option("--vary", multiple=True, metavar="NAME=VALUE", help="Vary the real workcell (docs/sweep.md).")
@click.option("--sample", metavar="FILE:N", help="Run in the workcell of run N of a sweep's results file.")
@click.option(
    "--ideal", is_flag=True, help="The ideal plant: the controller's model, exact encoders (docs/plant.md)."
)
@click.option(
    "--ros2",
    is_flag=True,
    help="Also log ROS 2 channels (JointState, WrenchStamped, TFMessage; CDR) for ros2 bag play.",
)
@click.option(
    "--live", is_flag=True, help="Stream the run to Foxglove (WebSocket on 127.0.0.1); implies --realtime."
)
@click.option("--port", type=click.IntRange(0, 65535), default=8765, show_default=True, help="--live port.")
@click.option("--realtime", is_flag=True, help="Run at the wall clock's pace (see --rate).")
@click.option(
    "--rate",
    type=click.FloatRange(min=0.01, max=100.0),
    default=None,
    help="Simulated seconds per wall-clock second (implies --realtime; default 1).",
)
@click.option(
    "--robot",
    type=click.Choice(sorted(ROBOTS), case_sensitive=False),
    default=None,
    help="The arm to run on (a program's ROBOT must agree; default: its ROBOT, else puma560).",
)
def run(
    program: Path,
    log_path: Path | None,
    servo_hz: float | None,
    param_hz: float | None,
    seed: int,
    force: bool,
    vary: tuple[str, ...],
    sample: str | None,
    ideal: bool,
    ros2: bool,
    live: bool,
    port: int,
    realtime: bool,
    rate: float | None,
    robot: str | None,
) -> None:
    """Check, compile and run PROGRAM on the simulated arm, logging to MCAP."""
    whole = bool(_WHOLE_PROCESS)
    with collector_off(whole):  # until the session is open (collect_from_here)
        with process.mujoco_without_gl() if whole else nullcontext():  # a run never renders
            with entry_points.unscanned() if whole else nullcontext():  # no extension, no plugin
                if whole:
                    process.numba_alone()
                from cosmos.commands.run import Pace, run_program
        from cosmos.runtime.rates import Rates

        rates = Rates.chosen(servo_hz or None, param_hz or None)
        variation = None
        if vary or sample is not None:  # the sweep's modules only when a run is varied
            from cosmos.commands.sweep import variation_for_run

            variation = variation_for_run(program, vary, sample, seed, ideal)
        paced = live or realtime or rate is not None
        pace = Pace(rate or 1.0, port if live else None) if paced else None
        status = run_program(
            program, log_path, rates, seed, force, variation, ros2=ros2, pace=pace, ideal=ideal, robot=robot
        )
    _finish(status)


@cli.command()
@program_argument
@click.option("--json", "as_json", is_flag=True, help="Print the plan as JSON.")
@click.option("--full", is_flag=True, help="Print every step of a long plan, not a summary.")
@click.option(
    "--robot",
    type=click.Choice(sorted(ROBOTS), case_sensitive=False),
    default=None,
    help="The arm to check for (a program's ROBOT must agree; default: its ROBOT, else puma560).",
)
def check(program: Path, as_json: bool, full: bool, robot: str | None) -> None:
    """Parse, check and compile PROGRAM without running it; print the plan."""
    with collector_off(bool(_WHOLE_PROCESS)):
        from cosmos.commands.check import check_program

        status = check_program(program, as_json, full=full, robot=robot)
    _finish(status)


@cli.command()
@click.option("--log", "log_path", type=click.Path(path_type=Path, readable=False), help="MCAP log path.")
@click.option("--force", is_flag=True, help="Overwrite the --log file if it exists.")
@click.option(
    "--robot",
    type=click.Choice(sorted(ROBOTS), case_sensitive=False),
    default=None,
    help="The arm to drive (default: puma560).",
)
@click.option(
    "--tool",
    type=click.Choice(["peg", "gripper"], case_sensitive=False),
    default="peg",
    show_default=True,
    help="The hand on the flange for the whole session (a session's TOOL cannot change it).",
)
def repl(log_path: Path | None, force: bool, robot: str | None, tool: str) -> None:
    """Interactive session on a live simulated arm."""
    from cosmos.commands.repl import run_repl

    _finish(run_repl(log_path, force, robot, tool))


@cli.command()
@click.argument("log", type=click.Path(path_type=Path, readable=False))
@click.option(
    "--plot",
    type=click.Path(path_type=Path, readable=False),
    help="Write position and force against time, statement by statement (PNG).",
)
@click.option(
    "--recover",
    "recover_to",
    type=click.Path(path_type=Path, readable=False),
    help="Write what is readable in a cut log to a complete MCAP file.",
)
@click.option("--view", is_flag=True, help="Play back in the MuJoCo viewer.")
@click.option("--video", type=click.Path(path_type=Path, readable=False), help="Render playback to MP4.")
@click.option("--verify", is_flag=True, help="Re-run the program and compare with the log.")
@click.option(
    "--rate",
    type=click.FloatRange(min=0.0, min_open=True),
    default=None,
    help="Playback speed of --view/--video: 2 plays twice as fast as the run.  [default: 1]",
)
@click.option(
    "--start",
    "start_s",
    type=click.FloatRange(min=0.0),
    default=None,
    help="Start --view/--video this many seconds into the run.  [default: 0]",
)
@click.option("--force", is_flag=True, help="Overwrite existing --recover, --plot and --video files.")
@click.option(
    "--topics",
    metavar="/A,/B",
    default=None,
    help="Print these channels' messages, decoded, one JSON line each (like mcap cat).",
)
def replay(
    log: Path,
    plot: Path | None,
    recover_to: Path | None,
    view: bool,
    video: Path | None,
    verify: bool,
    rate: float | None,
    start_s: float | None,
    force: bool,
    topics: str | None,
) -> None:
    """Summarise, plot, recover, play back or verify a run log."""
    from cosmos.commands.replay import ReplayOptions, replay_log

    if (rate is not None or start_s is not None) and not (view or video):
        raise UsageError("--rate and --start apply to --view and --video")
    options = ReplayOptions(
        plot=plot,
        recover_to=recover_to,
        view=view,
        video=video,
        verify=verify,
        rate=1.0 if rate is None else rate,
        start_s=0.0 if start_s is None else start_s,
        force=force,
        topics=tuple(t.strip() for t in (topics or "").split(",") if t.strip()),
    )
    _finish(replay_log(log, options))


@cli.command()
@program_argument
@click.option("--runs", type=click.IntRange(min=1), default=100, show_default=True, help="Runs to make.")
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="The sweep's seed: every run's draws.",
)
@click.option(
    "--vary", multiple=True, metavar="NAME=DIST", help="normal(mean, sd), uniform(lo, hi), a value."
)
@click.option("--workers", type=click.IntRange(min=1), default=None, help="Local processes [one a core].")
@click.option(
    "--cluster", metavar="ADDRESS", help="A Dask scheduler to run on (pip install 'cosmos-osc[cluster]')."
)
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path, readable=False),
    help="Results folder [sweeps/P-seedS].",
)
@click.option(
    "--keep",
    type=click.Choice(["all", "failed", "none"]),
    default="failed",
    show_default=True,
    help="Logs kept.",
)
@click.option(
    "--plot",
    type=click.Path(dir_okay=False, path_type=Path, readable=False),
    help="Success per parameter (PNG).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--ideal", is_flag=True, help="Every run on the ideal plant (docs/plant.md).")
def sweep(
    program: Path,
    runs: int,
    seed: int,
    vary: tuple[str, ...],
    workers: int | None,
    cluster: str | None,
    out: Path | None,
    keep: str,
    plot: Path | None,
    as_json: bool,
    ideal: bool,
) -> None:
    """Run PROGRAM many times in varied workcells; report its success rate (docs/sweep.md)."""
    from cosmos.commands.sweep import SweepOptions, run_sweep
    from cosmos.sweep.results import Keep

    if workers is not None and cluster is not None:
        raise UsageError("--workers and --cluster: the cluster's workers are its own")
    options = SweepOptions(program, runs, seed, vary, workers, cluster, out, Keep(keep), plot, as_json, ideal)
    _finish(run_sweep(options))


@cli.command()
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option(
    "--no-first-run",
    "skip_first",
    is_flag=True,
    help="Skip the first run in an empty kernel cache (it compiles every kernel: 30 s or more).",
)
def bench(as_json: bool, skip_first: bool) -> None:
    """Measure what users run (programs, start-up, a first run) and the servo loop, against a floor."""
    from cosmos.commands.bench import main as bench_main

    _finish(bench_main(as_json, first=not skip_first))


def main() -> None:
    """Entry point of the ``cosmos`` console script."""
    if sys._getframe(1).f_globals.get("__name__") == "__main__" and not _WHOLE_PROCESS:
        _WHOLE_PROCESS.append(True)  # called by the console script or ``python -m cosmos``, not a test
    try:
        try:
            cli.main(standalone_mode=True)
        except CosmosError as error:
            _report(error)
    except SystemExit as done:
        if not _WHOLE_PROCESS or not process.is_the_command():  # a script may catch it and go on
            raise
        process.end_process(done.code)
