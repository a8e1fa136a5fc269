"""``cosmos replay LOG``: summary of a run log, plot, recovery, playback, verification.

Each option is one step of :func:`replay_log`, run in this order: recover,
summarise, plot, view, video, verify. The exit status is 1 if ``--verify``
finds that the re-run departs from the log, else 0.

The log is untrusted input: it is read within caps and every message checked
(:func:`cosmos.runlog.read_log`; a bad log is one line and exit 1), and
everything printed from it has its control characters replaced. Outputs
(``--recover``, ``--plot``, ``--video``) follow :mod:`cosmos.runlog.output`: an
existing file is overwritten only with ``--force``.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import click

from cosmos.errors import UsageError
from cosmos.replay.summary import format_summary
from cosmos.replay.timeline import statement_timeline
from cosmos.runlog import read_log, recover
from cosmos.runlog.output import check_output

if TYPE_CHECKING:
    from cosmos.replay.playback import Playback, Video
    from cosmos.runlog.reader import RunRecord

EXIT_OK = 0
EXIT_DEPARTS = 1


@dataclass(frozen=True)
class ReplayOptions:
    """What ``cosmos replay`` was asked to do besides printing the summary.

    Attributes:
        plot: Write a PNG of position and force against time here.
        recover_to: Write the readable part of the log here as a complete MCAP file.
        view: Play the run back in the MuJoCo viewer.
        video: Render the playback to this MP4 file.
        verify: Re-run the program and compare with the log.
        rate: Playback speed for view and video: 2 plays twice as fast as the run.
        start_s: Simulated time at which view and video start [s].
        force: Overwrite existing output files.
        topics: Print the messages of these channels, one JSON line each, after the summary.
    """

    plot: Path | None = None
    recover_to: Path | None = None
    view: bool = False
    video: Path | None = None
    verify: bool = False
    rate: float = 1.0
    start_s: float = 0.0
    force: bool = False
    topics: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.rate > 0:
            raise UsageError(f"--rate must be > 0 (1 plays at the speed of the run); got {self.rate:g}")
        if not self.start_s >= 0:
            raise UsageError(f"--start must be >= 0 s; got {self.start_s:g}")


def replay_log(log: Path, options: ReplayOptions) -> int:
    """Run ``cosmos replay`` on ``log`` and return its exit status.

    Raises:
        CosmosError: If the log cannot be read, an output cannot be written,
            there is no display for ``--view``, or the log cannot be re-run.
    """
    outputs = ((options.recover_to, "the log"), (options.plot, "the plot"), (options.video, "the video"))
    for path, what in outputs:  # refused before any work is done
        if path is not None:
            check_output(path, what=what, force=options.force, reads=(log,))
    if options.video is not None:
        from cosmos.replay.playback import check_video_name, prefer_headless_gl

        check_video_name(options.video)  # refused before the summary is printed
        prefer_headless_gl()  # before anything imports mujoco
    if options.recover_to is not None:
        recovery = recover(log, options.recover_to, force=options.force)
        state = "was complete" if recovery.was_complete else "was cut short"
        click.echo(
            f"recovered {recovery.messages} messages up to t = {recovery.end_time_ns / 1e9:.3f} s "
            f"({recovery.readable_bytes} of {recovery.total_bytes} bytes readable; the log "
            f"{state}) into {options.recover_to}"
        )
        record = recovery.record
    else:
        record = read_log(log)
    timeline = statement_timeline(record)
    click.echo(format_summary(record, timeline))
    if options.topics:
        from cosmos.replay.topics import topic_lines

        for line in topic_lines(log if options.recover_to is None else options.recover_to, options.topics):
            click.echo(line)

    if options.plot is not None:
        from cosmos.replay.plot import plot_run  # matplotlib is slow to import

        click.echo(f"plot written to {plot_run(record, timeline, options.plot, options.force)}")

    if options.view or options.video is not None:
        from cosmos.replay.playback import Playback, view

        if options.start_s > record.end_time:
            end = f"t = {record.end_time:.3f} s"
            raise UsageError(f"--start {options.start_s:g} s is past the log's end, {end}")

        playback = Playback(start_s=options.start_s, rate=options.rate)
        if options.view:
            click.echo(
                f"playing from t = {options.start_s:g} s at {options.rate:g}x in the MuJoCo viewer; "
                "close its window to go on"
            )
            view(record, playback)
        if options.video is not None:
            video = _render_with_progress(record, options.video, playback, options.force)
            click.echo(
                f"video written to {video.path}: {video.frames} frames at {video.fps:g} fps, "
                f"t = {video.start_s:.3f} .. {video.end_s:.3f} s at {options.rate:g}x"
            )

    if options.verify:
        from cosmos.replay.verify import time_bound, verify_log

        click.echo(
            f"verify: re-running {record.metadata.get('program', 'the program')} "
            f"(stopped if it passes t = {time_bound(record.end_time):g} s: twice the logged "
            f"{record.end_time:.3f} s plus 10 s) ..."
        )
        verification = verify_log(record)
        click.echo(verification.render())
        if not verification.matches:
            return EXIT_DEPARTS
    return EXIT_OK


def _render_with_progress(record: RunRecord, path: Path, playback: Playback, force: bool) -> Video:
    """:func:`render_video`, with a frame counter on a terminal."""
    from cosmos.replay.playback import render_video

    if not sys.stderr.isatty():
        return render_video(record, path, playback, force=force)
    from rich.console import Console
    from rich.markup import escape

    shown = escape(str(path))
    with Console(stderr=True).status(f"rendering {shown}") as status:
        return render_video(
            record,
            path,
            playback,
            lambda k, n: status.update(f"rendering {shown}: frame {k + 1} of {n}"),
            force=force,
        )
