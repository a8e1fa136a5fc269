"""The shipped Foxglove layout (docs/foxglove-layout.json), built with foxglove-sdk's layout classes.

A 3D panel on the arm and workcell (``/tf``, ``/scene``, fixed frame ``world``,
the camera on the arm), plots of the tool position, force and moment from
``/cosmos/state``, the statement events (``/cosmos/log``) and the current
segment (``/cosmos/segment``). Written by::

    python -m cosmos.runlog.layout docs/foxglove-layout.json

and checked against the shipped file by ``tests/runlog/test_foxglove_layout.py``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import foxglove.layouts as fl

from cosmos.runlog.foxglove import LOG_TOPIC, SCENE_TOPIC, TRANSFORMS_TOPIC, WORLD_FRAME
from cosmos.runlog.schemas import SEGMENT_TOPIC, STATE_TOPIC

_CAMERA = fl.ThreeDeeCameraState(
    distance=2.4,
    perspective=True,
    phi=60,
    theta_offset=35,
    target=(0.35, 0.0, 0.25),  # the arm's workspace above the table
    target_offset=(0.0, 0.0, 0.0),
    target_orientation=(0.0, 0.0, 0.0, 1.0),
    fovy=45,
    near=0.01,
    far=100,
)


def _plot(title: str, field: str, first: int, labels: tuple[str, ...]) -> fl.PlotPanel:
    series = [
        fl.PlotSeries(
            value=f"{STATE_TOPIC}.{field}[{first + k}]",
            enabled=True,
            timestamp_method="receiveTime",
            label=label,
        )
        for k, label in enumerate(labels)
    ]
    config = fl.PlotConfig(
        paths=series,
        show_legend=True,
        legend_display="top",
        show_plot_values_in_legend=True,
        show_x_axis_labels=True,
        show_y_axis_labels=True,
        is_synced=True,
        x_axis_val="timestamp",
    )
    return fl.PlotPanel(title=title, config=config)


def build_layout() -> fl.Layout:
    """The layout: the 3D view on the left, plots, events and the segment on the right."""
    three_d = fl.ThreeDeePanel(
        title=f"arm and workcell ({TRANSFORMS_TOPIC}, {SCENE_TOPIC})",
        config=fl.ThreeDeeConfig(
            camera_state=_CAMERA,
            follow_mode="follow-none",
            follow_tf=WORLD_FRAME,
            fixed_frame=WORLD_FRAME,
            scene=fl.BaseRendererSceneSettings(
                transforms=fl.BaseRendererTransforms(show_label=False, axis_size=0.05)
            ),
            topics={SCENE_TOPIC: fl.BaseRendererSceneUpdateTopicSettings(visible=True)},
            layers={
                "grid": fl.BaseRendererGridLayerSettings(
                    layer_id="foxglove.Grid",
                    instance_id="grid",
                    visible=True,
                    label="Grid",
                    frame_id=WORLD_FRAME,
                    size=2,
                    divisions=20,
                    line_width=1,
                    color="#248eff",
                    position=(0.0, 0.0, 0.0),
                    rotation=(0.0, 0.0, 0.0),
                    order=1,
                )
            },
        ),
    )
    plots = fl.SplitContainer(
        direction="column",
        items=[
            fl.SplitItem(content=_plot(f"tool position [m] ({STATE_TOPIC}.x)", "x", 0, ("x", "y", "z"))),
            fl.SplitItem(
                content=_plot("force on environment [N] (wrench[0:3])", "wrench", 0, ("Fx", "Fy", "Fz"))
            ),
            fl.SplitItem(
                content=_plot("moment on environment [N m] (wrench[3:6])", "wrench", 3, ("Mx", "My", "Mz"))
            ),
        ],
    )
    events = fl.LogPanel(
        title=f"statement events ({LOG_TOPIC})",
        config=fl.LogConfig(topic_to_render=LOG_TOPIC, min_log_level=1, search_terms=[]),
    )
    segment = fl.RawMessagesPanel(
        title=f"current segment ({SEGMENT_TOPIC})",
        config=fl.RawMessagesConfig(topic_path=SEGMENT_TOPIC, diff_enabled=False, expansion="all"),
    )
    right = fl.SplitContainer(
        direction="column",
        items=[
            fl.SplitItem(proportion=3, content=plots),
            fl.SplitItem(proportion=1, content=events),
            fl.SplitItem(proportion=1, content=segment),
        ],
    )
    return fl.Layout(
        content=fl.SplitContainer(
            direction="row",
            items=[fl.SplitItem(proportion=3, content=three_d), fl.SplitItem(proportion=2, content=right)],
        )
    )


def layout_text() -> str:
    """The layout as the shipped file holds it: indented JSON and a final newline."""
    return json.dumps(json.loads(build_layout().to_json()), indent=2) + "\n"


def main(argv: list[str]) -> int:
    """Write the layout to the path given (``docs/foxglove-layout.json``)."""
    if len(argv) != 1:
        print("usage: python -m cosmos.runlog.layout docs/foxglove-layout.json", file=sys.stderr)
        return 2
    Path(argv[0]).write_text(layout_text())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
