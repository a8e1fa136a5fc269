import json
import math
import time
from datetime import UTC, datetime, timedelta, timezone
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from runlog_schema_check import foxglove_fields, validate
from runlog_synthetic import (
    PROGRAM,
    SEGMENTS,
    STATE_HZ,
    WrittenRun,
    open_log,
    segment_args,
    state_args,
    write_synthetic_run,
)

from cosmos.runlog import RunLog, default_log_path
from tests import foxglove_proto

COSMOS_TOPICS = {
    "/cosmos/state": "cosmos.State",
    "/cosmos/segment": "cosmos.Segment",
    "/cosmos/event": "cosmos.Event",
    "/tf": "foxglove.FrameTransforms",
    "/scene": "foxglove.SceneUpdate",
    "/cosmos/log": "foxglove.Log",
}


@pytest.fixture(scope="module")
def run_log(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, WrittenRun]:
    path = tmp_path_factory.mktemp("writer") / "nested" / "dir" / "run.mcap"
    return path, write_synthetic_run(path)


def messages_by_topic(path: Path) -> dict[str, list[tuple[dict, int, int]]]:
    """topic -> [(decoded message, log_time, publish_time)] read with mcap's own reader.

    JSON channels are decoded as JSON, protobuf ones with Foxglove's official compiled schemas.
    """
    out: dict[str, list[tuple[dict, int, int]]] = {}
    with open(path, "rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages():
            assert schema is not None
            if channel.message_encoding == "protobuf":
                decoded = foxglove_proto.decode(schema.name, message.data)
            else:
                decoded = json.loads(message.data)
            out.setdefault(channel.topic, []).append((decoded, message.log_time, message.publish_time))
    return out


def test_summary_lists_schemas_channels_and_counts(run_log: tuple[Path, WrittenRun]) -> None:
    path, written = run_log
    with open(path, "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None and summary.statistics is not None
    topics = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()}
    assert topics == COSMOS_TOPICS
    encodings = {
        c.topic: (c.message_encoding, summary.schemas[c.schema_id].encoding)
        for c in summary.channels.values()
    }
    assert encodings == {
        topic: ("protobuf", "protobuf") if name.startswith("foxglove.") else ("json", "jsonschema")
        for topic, name in COSMOS_TOPICS.items()
    }
    stats = summary.statistics
    counts = {summary.channels[c].topic: n for c, n in stats.channel_message_counts.items()}
    n_events = 2 * 4 + 1  # start and outcome of four statements, one contact
    assert counts == {
        "/cosmos/state": written.states,
        "/cosmos/segment": len(SEGMENTS),
        "/cosmos/event": n_events,
        "/cosmos/log": n_events,
        "/tf": math.ceil(written.states / 10),
        "/scene": 2,
    }
    assert summary.chunk_indexes, "the file must be indexed"


def test_log_time_is_simulated_time_in_nanoseconds(run_log: tuple[Path, WrittenRun]) -> None:
    for topic, messages in messages_by_topic(run_log[0]).items():
        for decoded, log_time, publish_time in messages:
            t = decoded["t"] if "t" in decoded else None
            assert log_time == publish_time
            if t is not None:
                assert log_time == round(t * 1e9), topic


def test_state_message_round_trips(run_log: tuple[Path, WrittenRun]) -> None:
    states = messages_by_topic(run_log[0])["/cosmos/state"]
    for k in (0, 1, 137, len(states) - 1):
        decoded = states[k][0]
        expected = state_args(k)
        assert decoded["t"] == expected["t"]
        assert decoded["segment"] == expected["segment"]
        assert decoded["line"] == expected["line"]
        for name in ("q", "qd", "tau", "x", "quat", "v", "wrench"):
            want = np.asarray(expected[name], dtype=float)
            got = np.asarray(decoded[name])
            assert got.shape == want.shape
            # written rounded to 1e-6 of the unit
            assert np.all(np.abs(got - want) <= 0.5e-6 + 1e-12), name


def test_segment_and_event_messages_round_trip_exactly(run_log: tuple[Path, WrittenRun]) -> None:
    by_topic = messages_by_topic(run_log[0])
    for index, (decoded, _, _) in enumerate(by_topic["/cosmos/segment"]):
        expected = segment_args(index)
        assert decoded["t"] == SEGMENTS[index][0]
        for key, value in expected.items():
            want = list(value) if isinstance(value, tuple) else value
            assert decoded[key] == want, key
    events = [d for d, _, _ in by_topic["/cosmos/event"]]
    assert events[0] == {
        "t": 0.0,
        "kind": "start",
        "line": 2,
        "statement": "MOVE TO hole + (0, 0, 80 mm)",
        "reason": "",
        "context": "",
    }
    failed = next(e for e in events if e["kind"] == "failed")
    assert failed == {
        "t": 4.0,
        "kind": "failed",
        "line": 5,
        "statement": "INSERT DOWN DEPTH 30 mm FORCE 15 N",
        "reason": "jammed at 10 mm",
        "context": "",
    }


def test_every_message_validates_against_its_channel_schema(
    run_log: tuple[Path, WrittenRun],
) -> None:
    with open(run_log[0], "rb") as stream:
        reader = make_reader(stream)
        checked = set()
        for schema, channel, message in reader.iter_messages():
            assert schema is not None
            if schema.encoding == "protobuf":  # strict decode with the official compiled schema
                foxglove_proto.decode(schema.name, message.data)
            else:
                errors = validate(json.loads(message.data), json.loads(schema.data))
                assert errors == [], (channel.topic, errors[:3])
            checked.add(channel.topic)
    assert checked == set(COSMOS_TOPICS)


def test_validator_rejects_what_the_schemas_forbid(run_log: tuple[Path, WrittenRun]) -> None:
    # The check above is only worth something if the schemas reject bad messages.
    with open(run_log[0], "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    schemas = {s.name: json.loads(s.data) for s in summary.schemas.values() if s.encoding == "jsonschema"}
    segment = {"t": 0.0, **segment_args(0)}
    segment = json.loads(json.dumps(segment))
    assert validate(segment, schemas["cosmos.Segment"]) == []
    assert validate({**segment, "goal": None, "timeout": None}, schemas["cosmos.Segment"]) == []
    assert validate({**segment, "goal": "up"}, schemas["cosmos.Segment"])
    assert validate({**segment, "motion_axes": [1, 1, 1]}, schemas["cosmos.Segment"])
    missing = dict(segment)
    del missing["speed_limit"]
    assert validate(missing, schemas["cosmos.Segment"])
    event = {"t": 1.0, "kind": "exploded", "line": 3, "statement": "x", "reason": ""}
    assert validate(event, schemas["cosmos.Event"])


def test_schemas_parse_as_foxglove_parses_json_schemas(run_log: tuple[Path, WrittenRun]) -> None:
    with open(run_log[0], "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    fields = {
        s.name: foxglove_fields(json.loads(s.data))
        for s in summary.schemas.values()
        if s.encoding == "jsonschema"
    }
    assert fields["cosmos.State"]["wrench"] == "number[]"


def test_foxglove_channels_store_the_official_protobuf_schemas(run_log: tuple[Path, WrittenRun]) -> None:
    """Catches a /tf, /scene or /cosmos/log schema that is not Foxglove's own .proto definition."""
    with open(run_log[0], "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    stored = {s.name: s.data for s in summary.schemas.values() if s.encoding == "protobuf"}
    assert set(stored) == set(foxglove_proto.OFFICIAL)
    for name, data in stored.items():
        assert foxglove_proto.stored_schema_is_official(name, data), name


def test_attachment_holds_the_program_and_metadata_the_run(
    run_log: tuple[Path, WrittenRun],
) -> None:
    with open(run_log[0], "rb") as stream:
        reader = make_reader(stream)
        attachments = list(reader.iter_attachments())
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
    assert [(a.name, a.media_type, a.data.decode()) for a in attachments] == [
        ("peg.cos", "text/plain", PROGRAM)
    ]
    record = metadata["cosmos"]
    assert record["program"] == "programs/peg.cos"
    assert record["servo_hz"] == "1000"
    assert record["param_hz"] == "200"
    assert record["state_hz"] == "250"
    assert record["model"] == "puma560"
    assert record["seed"] == "7"
    assert record["scene"] == "workcell"
    assert record["cosmos_version"]


def test_transforms_and_scene_messages_have_foxglove_shape(
    run_log: tuple[Path, WrittenRun],
) -> None:
    by_topic = messages_by_topic(run_log[0])
    tf, log_time, _ = by_topic["/tf"][3]  # sample 30
    transforms = tf["transforms"]
    assert [t["child_frame_id"] for t in transforms] == [
        "link1", "link2", "link3", "link4", "link5", "link6", "tool"
    ]  # fmt: skip
    first = transforms[0]
    assert first["parent_frame_id"] == "world"
    assert first["timestamp"] == {"sec": 0, "nsec": log_time}
    expected = state_args(30)["x"]
    got = [first["translation"][a] for a in "xyz"]
    assert np.allclose(got, expected, atol=1e-6)
    assert first["rotation"] == {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
    assert all(t["timestamp"] == first["timestamp"] for t in transforms)

    added, removed = (m[0] for m in by_topic["/scene"])
    entities = {e["id"]: e for e in added["entities"]}
    assert entities["table"]["cubes"][0]["size"] == {"x": 0.8, "y": 1.2, "z": 0.05}
    assert entities["post"]["cylinders"][0]["size"] == {"x": 0.08, "y": 0.08, "z": 0.6}
    assert entities["ball"]["spheres"][0]["size"] == {"x": 0.12, "y": 0.12, "z": 0.12}
    assert entities["ball"]["spheres"][0]["pose"]["position"] == {"x": 0.4, "y": 0.25, "z": 0.5}
    assert all(e["frame_id"] == "world" and not e["frame_locked"] for e in entities.values())
    assert all(e["lifetime"] == {"sec": 0, "nsec": 0} for e in entities.values())
    assert removed["entities"] == []
    assert [(d["id"], d["type"]) for d in removed["deletions"]] == [("ball", 0)]


def test_non_finite_state_values_are_written_as_null(tmp_path: Path) -> None:
    path = tmp_path / "nan.mcap"
    with open_log(path) as log:
        args = state_args(0)
        args["wrench"] = np.array([np.nan, 0.0, np.inf, 0.0, 0.0, 0.0])
        log.state(**args)
        log.state(**state_args(1))
    decoded = [m[0] for m in messages_by_topic(path)["/cosmos/state"]]
    assert decoded[0]["wrench"][:3] == [None, 0.0, None]
    assert decoded[1]["wrench"] == pytest.approx(list(state_args(1)["wrench"]), abs=1e-6)


def test_bad_arguments_are_refused_before_anything_is_written(tmp_path: Path) -> None:
    with open_log(tmp_path / "bad.mcap") as log:
        with pytest.raises(ValueError, match="kind"):
            log.event(0.0, "exploded", line=1, statement="MOVE")
        with pytest.raises(ValueError, match="motion_axes"):
            log.segment(0.0, **{**segment_args(0), "motion_axes": (1, 1, 2, 1, 1, 1)})
        with pytest.raises(ValueError, match="force_setpoint"):
            log.segment(0.0, **{**segment_args(0), "force_setpoint": (0.0, 0.0, 1.0)})
        with pytest.raises(ValueError):
            log.state(**{**state_args(0), "x": (0.0, 0.0, 0.0, 0.0)})
    assert messages_by_topic(tmp_path / "bad.mcap") == {}


def test_close_is_idempotent_and_runs_on_an_exception(tmp_path: Path) -> None:
    path = tmp_path / "boom.mcap"
    with pytest.raises(RuntimeError), open_log(path) as log:
        log.state(**state_args(0))
        raise RuntimeError("the runtime crashed")
    assert log.closed
    log.close()
    with pytest.raises(ValueError, match="closed"):
        log.event(1.0, "done", line=1, statement="MOVE")
    with open(path, "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None and summary.statistics is not None
    assert summary.statistics.message_count == 1


def test_default_log_path_uses_program_stem_and_utc() -> None:
    program = Path("programs/peg_in_hole.cos")
    aware = datetime(2026, 11, 22, 4, 15, 0, tzinfo=timezone(timedelta(hours=1)))
    assert default_log_path(program, aware) == Path("logs/peg_in_hole-20261122T031500Z.mcap")
    naive = datetime(2026, 11, 22, 3, 15, 0)
    assert default_log_path(program, naive) == Path("logs/peg_in_hole-20261122T031500Z.mcap")
    assert default_log_path(program, datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC)).name == (
        "peg_in_hole-20260102T030405Z.mcap"
    )


def naive_state_json(t: float, args: dict) -> bytes:
    """The obvious encoding: a dict of rounded lists through json.dumps."""
    message = {"t": t}
    for name in ("q", "qd", "tau", "x", "quat", "v", "wrench"):
        message[name] = [round(v, 6) for v in np.asarray(args[name]).tolist()]
    message["segment"], message["line"] = args["segment"], args["line"]
    return json.dumps(message).encode()


def best_us_per_call(run, n: int) -> float:
    """Best of three timings of ``run(n)``, in microseconds per call (robust to a busy machine)."""
    timings = []
    for _ in range(3):
        start = time.perf_counter()
        run(n)
        timings.append((time.perf_counter() - start) / n * 1e6)
    return min(timings)


def test_state_costs_less_than_encoding_it_naively(tmp_path: Path) -> None:
    """The runtime calls state() at 250 Hz of simulated time in a ~30k ticks/s loop."""
    samples = [state_args(k) for k in range(200)]
    log = RunLog(
        tmp_path / "bench.mcap",
        program="bench.cos",
        source="",
        servo_hz=1000,
        param_hz=250,
        state_hz=STATE_HZ,
        model="puma560",
        seed=0,
    )

    def log_states(n: int) -> None:
        for k in range(n):
            a = samples[k % 200]
            t = k / STATE_HZ
            log.state(t, a["q"], a["qd"], a["tau"], a["x"], a["quat"], a["v"], a["wrench"], 3, 12)
        log.flush()

    def encode_naively(n: int) -> None:
        for k in range(n):
            naive_state_json(k / STATE_HZ, samples[k % 200])

    with log:
        state_us = best_us_per_call(log_states, 10_000)
    naive_us = best_us_per_call(encode_naively, 10_000)
    # state() (copy, encode, MCAP record, compression) measured about 20 us on the
    # 2-core CI machine, the naive encoding alone about 60 us.
    assert state_us < 0.75 * naive_us, f"state() {state_us:.1f} us, naive json {naive_us:.1f} us"


def test_read_only_lists_and_strided_inputs_write_the_same_messages(tmp_path: Path) -> None:
    """state() and transforms() take any array-like: their kernels want writable float64 arrays."""

    def odd(value: object, k: int) -> object:
        array = np.array(value, dtype=float)
        if k == 0:
            array.flags.writeable = False
            return array
        if k == 1:
            return array.tolist()
        strided = np.repeat(array, 2, axis=0)[::2]  # not contiguous
        return strided

    plain, other = tmp_path / "plain.mcap", tmp_path / "other.mcap"
    for path, convert in ((plain, lambda v, k: v), (other, odd)):
        with open_log(path) as log:
            for k in range(3):
                args = state_args(k)
                for name in ("q", "qd", "tau", "x", "quat", "v", "wrench"):
                    args[name] = convert(args[name], k)
                log.state(**args)
                positions = np.tile(args["x"], (7, 1)) + np.arange(7)[:, None]
                log.transforms(args["t"], convert(positions, k), convert(np.tile([1.0, 0, 0, 0], (7, 1)), k))
    assert messages_by_topic(plain) == messages_by_topic(other)


def test_the_default_log_path_is_claimed_for_one_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches runs started in the same second sharing a default log name (three `cosmos.run`
    calls in threads, or three `cosmos run` processes, all wrote `logs/program-<second>.mcap`
    and two logs were lost): each call creates its own file, even from racing threads."""
    from concurrent.futures import ThreadPoolExecutor

    from cosmos.runlog.output import claim_log_path

    monkeypatch.chdir(tmp_path)
    now = datetime(2026, 11, 22, 3, 15, tzinfo=UTC)
    first = claim_log_path(Path("peg.cos"), now)
    assert first == Path("logs/peg-20261122T031500Z.mcap") and first.is_file()
    assert claim_log_path(Path("peg.cos"), now) == Path("logs/peg-20261122T031500Z-2.mcap")
    with ThreadPoolExecutor(8) as pool:
        claimed = list(pool.map(lambda _: claim_log_path(Path("peg.cos"), now), range(16)))
    assert len(set(claimed)) == 16
    assert {p.name for p in claimed} == {f"peg-20261122T031500Z-{n}.mcap" for n in range(3, 19)}


def test_log_channel_mirrors_each_event_with_its_level_and_line(run_log: tuple[Path, WrittenRun]) -> None:
    """Catches /cosmos/log (protobuf foxglove.Log) out of step with /cosmos/event: a missing line,
    another time, a wrong source line or file, or a failure not at ERROR level."""
    by_topic = messages_by_topic(run_log[0])
    events, logs = by_topic["/cosmos/event"], by_topic["/cosmos/log"]
    assert len(events) == len(logs)
    error, warning, info = 4, 3, 2  # foxglove.LogLevel (Log.proto)
    for (event, t_ns, _), (log, log_ns, _) in zip(events, logs, strict=True):
        assert log_ns == t_ns and log["timestamp"] == {"sec": t_ns // 10**9, "nsec": t_ns % 10**9}
        assert (log["file"], log["line"], log["name"]) == ("programs/peg.cos", event["line"], "cosmos")
        assert event["statement"] in log["message"]
        expected = {"failed": error, "protective_stop": error, "collision": warning}.get(event["kind"], info)
        assert log["level"] == expected, event
