"""Hypothesis: MCAP files of valid structure and hostile content never crash, hang or leak.

The strategy starts from valid cosmos messages and replaces fields by hostile
values (huge integers, floats past a double written as text, deep nesting,
non-JSON constants, control characters, wrong types), drops fields, or sends
raw bytes; metadata and the program carry hostile text; files are written with
each compression the ``mcap`` package offers and sometimes cut or damaged. The
property: :func:`read_log` returns a record whose text is printable and whose
state arrays are numbers, or raises a :class:`CosmosError` of one printable line
naming the file; :func:`recover` agrees with it; the summary printed is printable.
"""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from crafted_logs import event, metadata, segment, state, write_log
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mcap.writer import CompressionType

from cosmos.errors import CosmosError
from cosmos.replay.summary import format_summary
from cosmos.replay.timeline import statement_timeline
from cosmos.runlog import read_log, recover

UNPRINTABLE = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")
RAW = (
    b"1e400",
    b"-1e400",
    b"NaN",
    b"Infinity",
    b"[" * 3000,
    b"1" + b"0" * 5000,
    b"\xff\xfe",
    b"",
    b"{}",
    b"true",
)

hostile_text = st.text(
    alphabet=st.characters(codec="utf-8") | st.sampled_from("\x1b\x07\x9b\u202e\r\x00"), max_size=24
)
hostile_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**40), max_value=10**40)
    | st.floats(allow_nan=False, allow_infinity=False)
    | hostile_text,
    lambda children: (
        st.lists(children, max_size=8) | st.dictionaries(st.text(max_size=6), children, max_size=4)
    ),
    max_leaves=16,
)


@st.composite
def hostile_message(draw: st.DrawFn, valid: dict[str, Any]) -> bytes:
    """``valid`` with some fields replaced, removed, or spliced with raw text; or raw bytes."""
    if draw(st.integers(0, 9)) == 0:
        return draw(st.sampled_from(RAW) | st.binary(max_size=40))
    message = dict(valid)
    raw: dict[str, bytes] = {}
    for name in draw(st.lists(st.sampled_from(sorted(valid)), max_size=3, unique=True)):
        action = draw(st.integers(0, 2))
        if action == 0:
            message[name] = draw(hostile_values)
        elif action == 1:
            del message[name]
        else:
            raw[name] = draw(st.sampled_from(RAW))
    text = json.dumps(message).encode()
    for name, fragment in raw.items():
        text = re.sub(
            rb'("' + name.encode() + rb'": )(\[[^\]]*\]|[^,}]*)', lambda m, f=fragment: m.group(1) + f, text
        )
    return text


@st.composite
def hostile_logs(draw: st.DrawFn) -> dict[str, Any]:
    """Arguments of :func:`write_log`, plus how to cut or damage the file."""
    n = draw(st.integers(0, 25))
    return {
        "states": [
            draw(hostile_message(state(k))) if draw(st.integers(0, 4)) == 0 else state(k) for k in range(n)
        ],
        "segments": draw(st.lists(hostile_message(segment()), max_size=3)),
        "events": draw(st.lists(hostile_message(event()), max_size=4)),
        "meta": metadata(
            **draw(st.dictionaries(st.sampled_from(["program", "model", "servo_hz", "x"]), hostile_text))
        ),
        "program": draw(hostile_text),
        "compression": draw(st.sampled_from(list(CompressionType))),
        "cut": draw(st.none() | st.floats(0.0, 1.0)),
        "flip": draw(st.none() | st.floats(0.0, 1.0)),
    }


def _check_record_or_error(path: Path) -> str | None:
    """Read ``path``; check the record, or the error's one line; return that line (None if read)."""
    try:
        record = read_log(path)
    except CosmosError as error:
        line = error.render()
        assert line.startswith(f"{path}: ") and "\n" not in line and not UNPRINTABLE.search(line), line
        return line
    texts = [*record.metadata.keys(), *record.metadata.values(), record.source_name or ""]
    texts += [t for s in record.segments for t in (s.statement, s.kind)]
    texts += [t for e in record.events for t in (e.statement, e.kind, e.reason)]
    assert not any(UNPRINTABLE.search(text) for text in texts)
    assert record.state.q.dtype == np.float64 and record.state.line.dtype == np.int64
    assert np.isfinite(record.state.t).all()
    summary = format_summary(record, statement_timeline(record))
    assert not UNPRINTABLE.search(summary.replace("\n", " "))
    return None


@settings(max_examples=80, deadline=5000, suppress_health_check=[HealthCheck.too_slow])
@given(log=hostile_logs())
def test_hostile_content_is_read_or_refused_in_one_line(log: dict[str, Any]) -> None:
    """Catches any exception other than a one-line CosmosError (OverflowError, RecursionError,
    KeyError, AttributeError, numpy casting errors), control characters in what is printed, and
    --recover disagreeing with the reader."""
    cut, flip = log.pop("cut"), log.pop("flip")
    with tempfile.TemporaryDirectory() as directory:
        path = write_log(Path(directory) / "run.mcap", **log)
        data = bytearray(path.read_bytes())
        if flip is not None:
            data[8 + int(flip * (len(data) - 9))] ^= 0x5A
        if cut is not None:
            data = data[: int(cut * len(data))]
        path.write_bytes(bytes(data))
        refused = _check_record_or_error(path)
        out = Path(directory) / "out.mcap"
        try:
            recover(path, out)
        except CosmosError as error:
            assert refused is not None and error.render() == refused or "onto itself" in error.render()
        else:
            assert refused is None
            assert _check_record_or_error(out) is None
