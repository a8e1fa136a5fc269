"""A picture of a run: tool position, force and orientation against time, statement by statement.

Beside what the arm did, what each statement asked for: its goal and its force
setpoint (:mod:`cosmos.replay.setpoints`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from cosmos.errors import CosmosError
from cosmos.replay.setpoints import Step, force_steps, goal_steps, rpy_degrees
from cosmos.replay.summary import shorten
from cosmos.replay.timeline import StatementRun
from cosmos.runlog.output import written
from cosmos.runlog.printable import printable
from cosmos.runlog.reader import RunRecord, SegmentRecord

FORCE_SHADE = "#f2a541"
OUTCOME_COLORS = {"done": "#2b6cb0", "stopped": "#2f855a", "failed": "#c53030", "interrupted": "#b7791f"}
UNFINISHED_COLOR = "#718096"
PLOTTABLE = 1e9
"""Values of larger magnitude in SI units (a diverged run, or a crafted log) are left out of the plot,
as gaps (matplotlib fails on axes spanning ~1e300)."""


def _plottable(values: np.ndarray) -> np.ndarray:
    """``values`` with the non-finite and those past ``PLOTTABLE`` as NaN (matplotlib leaves a gap)."""
    return np.where(np.abs(values) < PLOTTABLE, values, np.nan)


def force_intervals(segments: Sequence[SegmentRecord], end: float) -> list[tuple[float, float]]:
    """Time intervals in which a translational task axis was force-controlled [s].

    A segment lasts from its start to the next segment's start (the last one to ``end``).
    Adjacent intervals are merged.
    """
    intervals: list[tuple[float, float]] = []
    for segment, following in zip(segments, [*segments[1:], None], strict=True):
        if not segment.force_controlled_translation:
            continue
        stop = end if following is None else following.t
        if intervals and intervals[-1][1] >= segment.t:
            intervals[-1] = (intervals[-1][0], max(stop, intervals[-1][1]))
        else:
            intervals.append((segment.t, stop))
    return intervals


def _mark_statements(axes: Sequence[Axes], timeline: Sequence[StatementRun]) -> None:
    top = axes[0]
    for run in timeline:
        if run.depth > 0 or run.between:
            continue
        color = OUTCOME_COLORS.get(run.outcome, UNFINISHED_COLOR)
        for ax in axes:
            ax.axvline(run.start, color="#4a5568", linewidth=0.8, linestyle="--", alpha=0.7)
        top.axvspan(run.start, run.end, ymin=0.95, ymax=1.0, color=color, alpha=0.8, linewidth=0)
        label = f"{run.line}: {shorten(run.statement, 40)}"
        if run.outcome not in ("done", "stopped"):
            label += f" [{run.outcome}]"
        top.text(
            run.start,
            1.02,
            label,
            transform=top.get_xaxis_transform(),
            rotation=50,
            rotation_mode="anchor",
            fontsize=7,
            color=color,
            ha="left",
            va="bottom",
            clip_on=False,
        )


def figure_for_run(record: RunRecord, timeline: Sequence[StatementRun]) -> Figure:
    """The figure of a run: x, y, z of the tool [mm] and the force it applies [N] against time.

    Statement starts are dashed lines labelled ``line: statement``, and a bar
    along the top spans each statement, coloured by outcome (blue done, green
    stopped, red failed, grey unfinished); intervals with a force-controlled
    translational axis are shaded.

    Raises:
        CosmosError: If the log has no state samples.
    """
    state = record.state
    if len(state) == 0:
        raise CosmosError(f"{record.path}: no state samples to plot")
    figure = Figure(figsize=(13, 12), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(5, 1, sharex=True, height_ratios=(1, 1, 1, 1.6, 1))
    end = record.end_time
    goals = goal_steps(record.segments, end)
    for ax, index, name in zip(axes[:3], range(3), "xyz", strict=False):
        ax.plot(state.t, _plottable(state.x[:, index]) * 1e3, color="#2d3748", linewidth=1.2)
        _draw_steps(ax, goals, index, 1e3, "#805ad5", "goal" if index == 0 else None)
        ax.set_ylabel(f"tool {name} [mm]")
        ax.ticklabel_format(axis="y", useOffset=False)
    force_ax, turn_ax = axes[3], axes[4]
    colors = ("#e53e3e", "#38a169", "#3182ce")
    for index, (name, color) in enumerate(zip("xyz", colors, strict=True)):
        force_ax.plot(
            state.t, _plottable(state.wrench[:, index]), color=color, linewidth=1.0, label=f"F{name}"
        )
    magnitude = np.linalg.norm(_plottable(state.wrench[:, :3]), axis=1)
    force_ax.plot(state.t, magnitude, color="black", linewidth=1.6, label="|F|")
    setpoints = force_steps(record.segments, end)
    for index, color in enumerate(colors):
        label = "force setpoint" if index == 0 else None
        _draw_steps(force_ax, setpoints, index, 1.0, color, label, linestyle="-.")
    force_ax.set_ylabel("force on environment [N]")
    force_ax.axhline(0.0, color="#a0aec0", linewidth=0.6)
    angles = rpy_degrees(state.quat)
    for index, (name, color) in enumerate(zip(("roll", "pitch", "yaw"), colors, strict=True)):
        turn_ax.plot(state.t, angles[:, index], color=color, linewidth=1.0, label=name)
    turn_ax.set_ylabel("tool RPY [deg]")
    turn_ax.set_xlabel("simulated time [s]")
    for number, (start, stop) in enumerate(force_intervals(record.segments, end)):
        for ax in axes:
            ax.axvspan(
                start,
                stop,
                color=FORCE_SHADE,
                alpha=0.18,
                linewidth=0,
                label="force-controlled" if number == 0 and ax is force_ax else None,
            )
    _mark_statements(axes, timeline)
    if record.truncated:
        for ax in axes:
            ax.axvline(end, color="#c53030", linewidth=1.5)
        force_ax.annotate(
            "log cut here",
            (end, 0.95),
            xycoords=force_ax.get_xaxis_transform(),
            ha="right",
            va="top",
            color="#c53030",
            fontsize=8,
        )
    outcomes = sorted({run.outcome for run in timeline if run.depth == 0})
    handles = [h for ax in (axes[0], force_ax, turn_ax) for h in ax.get_legend_handles_labels()[0]]
    handles += [
        Patch(color=OUTCOME_COLORS.get(outcome, UNFINISHED_COLOR), label=f"statement {outcome}")
        for outcome in outcomes
    ]
    # Below the panels, never over the data.
    figure.legend(handles=handles, loc="outside lower center", fontsize=8, ncols=len(handles))
    axes[0].set_ymargin(0.15)  # keep the curve clear of the statement bar
    first, last = float(np.min(state.t)), max(end, float(np.max(state.t)))
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if last > first:
            ax.set_xlim(first, last)
    program = record.metadata.get("program", record.path.name)
    figure.suptitle(f"{program}: tool position, force and orientation", fontsize=11)
    return figure


def _draw_steps(
    ax: Axes,
    steps: Sequence[Step],
    index: int,
    scale: float,
    color: str,
    label: str | None,
    linestyle: str = ":",
) -> None:
    """Component ``index`` of each step, times ``scale``, as a horizontal line over its interval."""
    for number, step in enumerate(steps):
        value = float(_plottable(step.value[index : index + 1])[0]) * scale
        ax.plot(
            (step.start, step.stop),
            (value, value),
            color=color,
            linewidth=1.4,
            linestyle=linestyle,
            label=label if number == 0 else None,
        )


def plot_run(record: RunRecord, timeline: Sequence[StatementRun], out: Path, force: bool = False) -> Path:
    """Write :func:`figure_for_run` to ``out`` as a PNG and return ``out``.

    Args:
        record: The log.
        timeline: Its statements.
        out: The PNG file (see :mod:`cosmos.runlog.output` for what may be written).
        force: Overwrite ``out`` if it exists.

    Raises:
        CosmosError: If the log has no state samples.
        UsageError: If the file cannot be written, naming it and the reason.
    """
    try:
        figure = figure_for_run(record, timeline)
        with written(out, what="the plot", force=force) as stream:
            figure.savefig(stream, dpi=100, format="png")
    except (ValueError, OverflowError, np.linalg.LinAlgError) as error:  # matplotlib on extreme data
        out.unlink(missing_ok=True)
        raise CosmosError(f"{record.path}: cannot plot this log: {printable(str(error))[:200]}") from None
    return out
