"""docs/foxglove-layout.json is the SDK-built layout and names the topics and fields the writer writes."""

import json
import re
from pathlib import Path
from typing import Any

from cosmos.runlog import foxglove
from cosmos.runlog.layout import layout_text
from cosmos.runlog.schemas import SEGMENT_TOPIC, STATE_TOPIC, STATE_VECTORS

LAYOUT = Path(__file__).resolve().parents[2] / "docs" / "foxglove-layout.json"
WRITTEN_TOPICS = {
    STATE_TOPIC,
    SEGMENT_TOPIC,
    foxglove.TRANSFORMS_TOPIC,
    foxglove.SCENE_TOPIC,
    foxglove.LOG_TOPIC,
}


def panels_in(tree: dict[str, Any]) -> list[dict[str, Any]]:
    if tree["type"] == "panel":
        return [tree]
    return [panel for item in tree["items"] for panel in panels_in(item["content"])]


def test_shipped_layout_is_the_scripts_output() -> None:
    """Catches a hand edit of the shipped layout, or a change to the script not written out
    (python -m cosmos.runlog.layout docs/foxglove-layout.json)."""
    assert LAYOUT.read_text() == layout_text()


def test_layout_panels_read_written_topics_and_fields() -> None:
    """Catches a panel on a topic or state field the writer does not write (an empty panel)."""
    layout = json.loads(LAYOUT.read_text())
    panels = panels_in(layout["content"])
    kinds = {p["panelType"] for p in panels}
    assert {"ThreeDee", "Plot", "Log", "RawMessages"} <= kinds

    lengths = dict(STATE_VECTORS)
    plotted = []
    for panel in panels:
        for path in panel["config"].get("paths", []):
            match = re.fullmatch(r"(/[\w/]+)\.(\w+)\[(\d+)\]", path["value"])
            assert match, path["value"]
            topic, field, index = match[1], match[2], int(match[3])
            assert topic == STATE_TOPIC
            assert index < lengths[field], path["value"]
            plotted.append((field, index))
        assert panel["config"].get("legendDisplay", "top") != "floating"  # not over the data
    assert {("x", 0), ("x", 1), ("x", 2), ("wrench", 0), ("wrench", 1), ("wrench", 2)} <= set(plotted)
    three_d = next(p["config"] for p in panels if p["panelType"] == "ThreeDee")
    assert three_d["followTf"] == three_d["fixedFrame"] == foxglove.WORLD_FRAME
    assert set(three_d["topics"]) <= WRITTEN_TOPICS
    target = three_d["cameraState"]["target"]
    assert 0.0 < target[0] < 0.8 and abs(target[1]) < 0.5 and 0.0 < target[2] < 1.0  # on the arm
    log_panel = next(p["config"] for p in panels if p["panelType"] == "Log")
    assert log_panel["topicToRender"] == foxglove.LOG_TOPIC
    raw = [p["config"]["topicPath"] for p in panels if p["panelType"] == "RawMessages"]
    assert set(raw) <= WRITTEN_TOPICS
