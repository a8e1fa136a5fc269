import json
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.writer import Writer
from runlog_synthetic import (
    PROGRAM,
    SEGMENTS,
    STATE_HZ,
    STATEMENTS,
    WrittenRun,
    state_args,
    write_synthetic_run,
)

from cosmos.errors import CosmosError, UsageError
from cosmos.runlog import read_log, recover
from cosmos.runlog import scan as scan_module


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> WrittenRun:
    return write_synthetic_run(tmp_path_factory.mktemp("reader") / "run.mcap")


def expected_states(n: int) -> dict[str, np.ndarray]:
    samples = [state_args(k) for k in range(n)]
    return {
        name: np.array([s[name] for s in samples], dtype=float)
        for name in ("t", "q", "qd", "tau", "x", "quat", "v", "wrench", "segment", "line")
    }


def test_complete_log_reads_everything(written: WrittenRun) -> None:
    record = read_log(written.path)
    assert not record.truncated
    assert record.readable_bytes == record.total_bytes == written.path.stat().st_size
    assert record.source == PROGRAM and record.source_name == "peg.cos"
    assert record.metadata["model"] == "puma560"
    assert len(record.state) == written.states
    expected = expected_states(written.states)
    for name, want in expected.items():
        got = getattr(record.state, name)
        assert got.shape[0] == written.states
        assert np.allclose(got, want.reshape(got.shape), atol=0.5e-6 + 1e-12), name
    assert record.state.q.shape == (written.states, 6)
    assert record.state.segment.dtype == np.int64
    with pytest.raises(ValueError):
        record.state.x[0, 0] = 1.0  # read-only
    assert [(s.t, s.line, s.kind, s.motion_axes) for s in record.segments] == [
        (t, line, kind, axes) for t, line, kind, axes in SEGMENTS
    ]
    assert record.segments[0].goal == (0.5, 0.1, 0.1)
    assert record.segments[1].goal is None and record.segments[1].timeout is None
    kinds = [(e.kind, e.line) for e in record.events]
    assert kinds[:3] == [("start", 2), ("done", 2), ("start", 3)]
    assert ("contact", 3) in kinds and kinds[-1] == ("failed", 5)
    assert record.message_counts["/cosmos/state"] == written.states
    assert record.end_time == pytest.approx(4.0)


def test_the_walk_reads_what_the_mcap_package_reads_through_the_summary(written: WrittenRun) -> None:
    """The bounded record walk (which replaced reading through the summary) must find every
    message, attachment and metadata record that the mcap package finds through the index."""
    with open(written.path, "rb") as stream:
        reader = make_reader(stream)
        expected = [(c.topic, m.log_time, m.data) for _, c, m in reader.iter_messages(log_time_order=False)]
        attachments = [(a.name, a.data) for a in reader.iter_attachments()]
        metadata = [(m.name, m.metadata) for m in reader.iter_metadata()]
    contents = scan_module.load_mcap(written.path)
    walked = [(contents.channels[m.channel_id].topic, m.log_time, m.data) for m in contents.messages]
    assert walked == expected
    assert [(a.name, a.data) for a in contents.attachments] == attachments
    assert [(m.name, m.metadata) for m in contents.metadata] == metadata
    assert contents.complete


def cut_copy(source: Path, size: int, directory: Path) -> Path:
    out = directory / f"cut-{size}.mcap"
    out.write_bytes(source.read_bytes()[:size])
    return out


def test_cut_log_reads_up_to_the_last_flush(written: WrittenRun, tmp_path: Path) -> None:
    total = written.path.stat().st_size
    full = read_log(written.path)
    flushes = written.flushes
    offsets = [size for size, _ in flushes] + [size + 1 for size, _ in flushes]
    offsets += [(a + b) // 2 for (a, _), (b, _) in zip(flushes, flushes[1:], strict=False)]
    for size in sorted(set(offsets)):
        record = read_log(cut_copy(written.path, size, tmp_path))
        assert record.truncated, size
        assert record.total_bytes == size
        flushed = max(states for flush_size, states in flushes if flush_size <= size)
        assert len(record.state) == flushed, size
        assert np.array_equal(record.state.wrench, full.state.wrench[:flushed])
        assert record.events == full.events[: len(record.events)]
        assert all(e.t <= flushed / STATE_HZ for e in record.events)
    # cut inside the footer: every message is there, but the file is still incomplete
    record = read_log(cut_copy(written.path, total - 1, tmp_path))
    assert record.truncated and len(record.state) == written.states


@pytest.mark.parametrize("fraction", [0.3, 0.55, 0.8, 0.97])
def test_recovered_file_is_indexed(written: WrittenRun, tmp_path: Path, fraction: float) -> None:
    cut = cut_copy(written.path, int(written.path.stat().st_size * fraction), tmp_path)
    before = read_log(cut)
    out = tmp_path / "recovered.mcap"
    recovery = recover(cut, out)
    with open(out, "rb") as stream:
        reader = make_reader(stream)
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None
        assert summary.chunk_indexes
        assert summary.statistics.message_count == sum(before.message_counts.values())
        assert [a.name for a in reader.iter_attachments()] == ["peg.cos"]
        assert [m.name for m in reader.iter_metadata()] == ["cosmos"]
    after = read_log(out)
    assert not after.truncated
    assert recovery.messages == sum(before.message_counts.values())
    assert not recovery.was_complete
    assert after.message_counts == before.message_counts
    assert np.array_equal(after.state.x, before.state.x)
    assert after.events == before.events and after.segments == before.segments
    assert after.source == PROGRAM
    assert cut.read_bytes() == written.path.read_bytes()[: cut.stat().st_size]  # input untouched


def test_recover_refuses_to_overwrite_its_input(written: WrittenRun, tmp_path: Path) -> None:
    cut = cut_copy(written.path, 5000, tmp_path)
    with pytest.raises(UsageError, match="onto itself"):
        recover(cut, cut)


def test_damaged_chunk_reads_what_precedes_it(written: WrittenRun, tmp_path: Path) -> None:
    with open(written.path, "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    chunk = summary.chunk_indexes[len(summary.chunk_indexes) // 2]
    data = bytearray(written.path.read_bytes())
    data[chunk.chunk_start_offset + chunk.chunk_length // 2] ^= 0xFF
    damaged = tmp_path / "damaged.mcap"
    damaged.write_bytes(bytes(data))
    record = read_log(damaged)
    assert record.truncated
    before_chunk = max(s for size, s in written.flushes if size <= chunk.chunk_start_offset)
    assert len(record.state) == before_chunk


def test_missing_file_is_a_usage_error(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match="no such file"):
        read_log(tmp_path / "nope.mcap")


@pytest.mark.parametrize(
    ("content", "message"),
    [(b"", "not an MCAP file \\(empty\\)"), (b"MOVE TO (0, 0, 0)\n", "not an MCAP file")],
)
def test_a_file_that_is_not_mcap_is_refused(tmp_path: Path, content: bytes, message: str) -> None:
    path = tmp_path / "bad.mcap"
    path.write_bytes(content)
    with pytest.raises(CosmosError, match=message) as error:
        read_log(path)
    assert str(path) in str(error.value)


def test_an_mcap_file_of_something_else_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "other.mcap"
    with open(path, "wb") as stream:
        writer = Writer(stream)
        writer.start()
        schema = writer.register_schema("x", "jsonschema", b"{}")
        channel = writer.register_channel("/chatter", "json", schema)
        writer.add_message(channel, log_time=0, data=json.dumps({"a": 1}).encode(), publish_time=0)
        writer.finish()
    with pytest.raises(CosmosError, match="not a cosmos run log"):
        read_log(path)


def test_statement_events_match_the_program(written: WrittenRun) -> None:
    record = read_log(written.path)
    starts = [(e.t, e.line, e.statement) for e in record.events if e.kind == "start"]
    assert starts == [(s.start, s.line, s.text) for s in STATEMENTS]
