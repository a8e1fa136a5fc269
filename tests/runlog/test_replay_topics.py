"""`cosmos replay LOG --topics` prints the chosen channels' messages, decoded, in time order."""

import json
from pathlib import Path

import pytest
from mcap.reader import make_reader
from runlog_synthetic import write_synthetic_run

from cosmos.errors import UsageError
from cosmos.replay.topics import topic_lines


def test_topics_prints_each_message_decoded_in_time_order(tmp_path: Path) -> None:
    """Catches --topics dropping or reordering messages, printing raw protobuf, or mixing in
    channels not asked for (checked against the mcap package's own reader)."""
    path = tmp_path / "run.mcap"
    write_synthetic_run(path)
    lines = [json.loads(line) for line in topic_lines(path, ["/cosmos/event", "/tf"])]
    with open(path, "rb") as stream:
        expected = [
            (message.log_time, channel.topic)
            for _, channel, message in make_reader(stream).iter_messages(topics=["/cosmos/event", "/tf"])
        ]
    assert [(round(line["t"] * 1e9), line["topic"]) for line in lines] == expected
    events = [line["message"] for line in lines if line["topic"] == "/cosmos/event"]
    assert events[0]["kind"] == "start" and events[0]["line"] == 2
    frames = [line["message"] for line in lines if line["topic"] == "/tf"]
    assert [f["child_frame_id"] for f in frames[0]["transforms"]][-1] == "tool"


def test_topics_names_a_missing_channel_and_the_ones_there(tmp_path: Path) -> None:
    """Catches a typo in --topics printing nothing (the user cannot tell it from an empty channel)."""
    path = tmp_path / "run.mcap"
    write_synthetic_run(path)
    with pytest.raises(UsageError, match=r"no channel /cosmos/stat \(it has .*/cosmos/state"):
        list(topic_lines(path, ["/cosmos/stat"]))
