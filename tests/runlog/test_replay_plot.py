from pathlib import Path

import pytest
from matplotlib.colors import to_hex
from PIL import Image
from runlog_synthetic import FORCE_CONTROLLED, STATEMENTS, WrittenRun, write_synthetic_run

from cosmos.errors import CosmosError
from cosmos.replay.plot import FORCE_SHADE, figure_for_run, force_intervals, plot_run
from cosmos.replay.timeline import statement_timeline
from cosmos.runlog import read_log
from cosmos.runlog.reader import SegmentRecord


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> WrittenRun:
    return write_synthetic_run(tmp_path_factory.mktemp("plot") / "run.mcap")


def segment(t: float, axes: tuple[int, ...]) -> SegmentRecord:
    zeros = (0.0,) * 6
    return SegmentRecord(
        t, 0, 1, "S", "move", (1.0, 0.0, 0.0, 0.0), axes, zeros, zeros, zeros, None, None, None
    )


def test_force_intervals_merge_adjacent_and_split_on_motion() -> None:
    motion, force_z, force_all = (1,) * 6, (1, 1, 0, 1, 1, 1), (0, 0, 0, 0, 0, 1)
    rotation_only = (1, 1, 1, 0, 1, 1)
    segments = [
        segment(0.0, motion),
        segment(1.0, force_z),
        segment(2.0, force_all),
        segment(3.0, motion),
        segment(4.0, rotation_only),
        segment(5.0, force_z),
    ]
    assert force_intervals(segments, end=6.5) == [(1.0, 3.0), (5.0, 6.5)]


def shaded_spans(ax) -> list[tuple[float, float]]:
    spans = []
    for patch in ax.patches:
        if to_hex(patch.get_facecolor(), keep_alpha=False) == FORCE_SHADE:
            x0 = patch.get_x()
            spans.append((round(x0, 9), round(x0 + patch.get_width(), 9)))
    return spans


def test_figure_has_position_and_force_panels_marked_by_statement(written: WrittenRun) -> None:
    record = read_log(written.path)
    figure = figure_for_run(record, statement_timeline(record))
    axes = figure.axes
    assert len(axes) == 5
    assert [ax.get_ylabel() for ax in axes] == [
        "tool x [mm]",
        "tool y [mm]",
        "tool z [mm]",
        "force on environment [N]",
        "tool RPY [deg]",
    ]
    assert len(axes[3].get_lines()) >= 4  # Fx, Fy, Fz, |F|
    labels = [text.get_text() for text in axes[0].texts]
    assert labels == [
        f"{s.line}: {s.text}" + ("" if s.outcome in ("done", "stopped") else f" [{s.outcome}]")
        for s in STATEMENTS
    ]
    for ax in axes:
        assert shaded_spans(ax) == list(FORCE_CONTROLLED)
        starts = {line.get_xdata()[0] for line in ax.get_lines() if line.get_linestyle() == "--"}
        assert starts == {s.start for s in STATEMENTS}


def test_plot_writes_a_png(written: WrittenRun, tmp_path: Path) -> None:
    record = read_log(written.path)
    out = plot_run(record, statement_timeline(record), tmp_path / "run.png")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.stat().st_size > 30_000
    with Image.open(out) as image:
        assert image.size == (1300, 1200)


def test_plot_of_a_log_without_states_is_an_error(written: WrittenRun, tmp_path: Path) -> None:
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(written.path.read_bytes()[: written.flushes[0][0]])
    record = read_log(cut)
    with pytest.raises(CosmosError, match="no state samples"):
        figure_for_run(record, statement_timeline(record))


def test_legend_is_off_the_data_and_the_title_names_the_program(written: WrittenRun) -> None:
    """Catches a legend drawn inside a panel (over the curves) or a title without the program."""
    record = read_log(written.path)
    figure = figure_for_run(record, statement_timeline(record))
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    (legend,) = figure.legends
    box = legend.get_window_extent(renderer)
    assert all(ax.get_legend() is None for ax in figure.axes)
    for ax in figure.axes:
        assert not box.overlaps(ax.get_window_extent(renderer)), ax.get_ylabel()
    assert {t.get_text() for t in legend.get_texts()} >= {"Fx", "Fy", "Fz", "|F|"}
    assert record.metadata["program"] in figure.get_suptitle()


def test_setpoints_are_drawn_where_the_segments_asked_for_them(written: WrittenRun) -> None:
    """Catches goals or force setpoints drawn at the wrong height or over the wrong interval
    (checked against the segments as the mcap package's reader gives them)."""
    record = read_log(written.path)
    figure = figure_for_run(record, statement_timeline(record))
    force_ax = figure.axes[3]
    fz_color = next(line.get_color() for line in force_ax.get_lines() if line.get_label() == "Fz")
    fz = {
        (tuple(float(x) for x in line.get_xdata()), float(line.get_ydata()[0]))
        for line in force_ax.get_lines()
        if line.get_linestyle() == "-." and line.get_color() == fz_color
    }
    segments = sorted(record.segments, key=lambda s: s.t)
    expected = set()
    for k, segment in enumerate(segments):
        if 0 in segment.motion_axes[:3]:
            stop = segments[k + 1].t if k + 1 < len(segments) else record.end_time
            assert segment.frame == (0.0, 1.0, 0.0, 0.0)  # half a turn about x: task z is world -z
            fz_set = -segment.force_setpoint[2] * (1 - segment.motion_axes[2])
            expected.add(((segment.t, stop), fz_set))
    assert fz == expected
