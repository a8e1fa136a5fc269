"""The replay summary lists channels, rates, size and compression as `mcap info` does."""

from pathlib import Path

import pytest
from mcap.reader import make_reader
from runlog_synthetic import STATE_HZ, write_synthetic_run

from cosmos.replay.summary import format_summary
from cosmos.runlog import read_log


def test_summary_channels_and_chunks_agree_with_the_mcap_summary(tmp_path: Path) -> None:
    """Catches a summary whose schema names, encodings, counts, rates or compression figures
    are not the file's (checked against the mcap package's own summary section)."""
    path = tmp_path / "run.mcap"
    write_synthetic_run(path)
    record = read_log(path)
    text = format_summary(record, ())
    with open(path, "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None and summary.statistics is not None
    counts = summary.statistics.channel_message_counts
    for cid, channel in summary.channels.items():
        schema = summary.schemas[channel.schema_id].name
        row = next(line for line in text.splitlines() if line.strip().startswith(channel.topic + " "))
        assert f" {counts[cid]} msgs" in row and schema in row and f"[{channel.message_encoding}]" in row
    state = next(c for c in record.channels if c.topic == "/cosmos/state")
    assert state.rate_hz == pytest.approx(STATE_HZ, rel=1e-6)
    packed = sum(c.compressed_size for c in summary.chunk_indexes)
    unpacked = sum(c.uncompressed_size for c in summary.chunk_indexes)
    compressions = {c.compression for c in summary.chunk_indexes}
    assert set(record.chunks) == compressions
    assert sum(n for n, _, _ in record.chunks.values()) == len(summary.chunk_indexes)
    assert sum(p for _, p, _ in record.chunks.values()) == packed
    assert sum(u for _, _, u in record.chunks.values()) == unpacked
    assert f"{len(summary.chunk_indexes)} chunks zstd" in text
