"""docs/foxglove-layout.json must name the topics and fields the writer writes."""

import json
import re
from pathlib import Path
from typing import Any

from cosmos.runlog import foxglove
from cosmos.runlog.schemas import SEGMENT_TOPIC, STATE_TOPIC, STATE_VECTORS

LAYOUT = Path(__file__).resolve().parents[2] / "docs" / "foxglove-layout.json"
WRITTEN_TOPICS = {
    STATE_TOPIC,
    SEGMENT_TOPIC,
    foxglove.TRANSFORMS_TOPIC,
    foxglove.SCENE_TOPIC,
    foxglove.LOG_TOPIC,
}


def panels_in(tree: Any) -> list[str]:
    if isinstance(tree, str):
        return [tree]
    return panels_in(tree["first"]) + panels_in(tree["second"])


def test_layout_panels_are_configured_and_read_written_topics() -> None:
    layout = json.loads(LAYOUT.read_text())
    config = layout["configById"]
    assert sorted(panels_in(layout["layout"])) == sorted(config)
    kinds = {panel_id.split("!")[0] for panel_id in config}
    assert {"3D", "Plot", "RosOut"} <= kinds

    lengths = dict(STATE_VECTORS)
    plotted = []
    for panel_id, panel in config.items():
        for path in panel.get("paths", []):
            match = re.fullmatch(r"(/[\w/]+)\.(\w+)\[(\d+)\]", path["value"])
            assert match, path["value"]
            topic, field, index = match[1], match[2], int(match[3])
            assert topic == STATE_TOPIC, panel_id
            assert index < lengths[field], path["value"]
            plotted.append((field, index))
    assert {("x", 0), ("x", 1), ("x", 2), ("wrench", 0), ("wrench", 1), ("wrench", 2)} <= set(plotted)
    three_d = next(p for i, p in config.items() if i.startswith("3D!"))
    assert three_d["followTf"] == foxglove.WORLD_FRAME
    assert set(three_d["topics"]) <= WRITTEN_TOPICS
    log_panel = next(p for i, p in config.items() if i.startswith("RosOut!"))
    assert log_panel["topicToRender"] == foxglove.LOG_TOPIC
    raw = [p["topicPath"] for i, p in config.items() if i.startswith("RawMessages!")]
    assert set(raw) <= WRITTEN_TOPICS
