"""``cosmos replay LOG``: summary of a run log, plot, recovery; playback and verify later.

Each option is one step of :func:`replay_log`, run in this order: recover,
summarise, plot, then the steps that need the live runtime (view, video,
verify), which are not built yet.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import click

from cosmos.errors import CosmosError
from cosmos.replay.summary import format_summary
from cosmos.replay.timeline import statement_timeline
from cosmos.runlog import read_log, recover

EXIT_OK = 0


@dataclass(frozen=True)
class ReplayOptions:
    """What ``cosmos replay`` was asked to do besides printing the summary.

    Attributes:
        plot: Write a PNG of position and force against time here.
        recover_to: Write the readable part of the log here as a complete MCAP file.
        view: Play the run back in the MuJoCo viewer.
        video: Render the playback to this MP4 file.
        verify: Re-run the program and compare with the log.
    """

    plot: Path | None = None
    recover_to: Path | None = None
    view: bool = False
    video: Path | None = None
    verify: bool = False


def replay_log(log: Path, options: ReplayOptions) -> int:
    """Run ``cosmos replay`` on ``log`` and return its exit status.

    Raises:
        CosmosError: If the log cannot be read, an output cannot be written, or
            an option needs what is not built yet.
    """
    unbuilt = {"--view": options.view, "--video": options.video, "--verify": options.verify}
    for option, requested in unbuilt.items():
        if requested:
            raise CosmosError(f"cosmos replay {option}: not built yet")

    if options.recover_to is not None:
        recovery = recover(log, options.recover_to)
        state = "was complete" if recovery.was_complete else "was cut short"
        click.echo(
            f"recovered {recovery.messages} messages up to t = {recovery.end_time_ns / 1e9:.3f} s "
            f"({recovery.readable_bytes} of {recovery.total_bytes} bytes readable; the log "
            f"{state}) into {options.recover_to}"
        )

    record = read_log(log)
    timeline = statement_timeline(record)
    click.echo(format_summary(record, timeline))

    if options.plot is not None:
        from cosmos.replay.plot import plot_run  # matplotlib is slow to import

        click.echo(f"plot written to {plot_run(record, timeline, options.plot)}")
    return EXIT_OK
