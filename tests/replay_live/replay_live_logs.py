"""Real run logs for the replay tests: tiny programs run on the simulated arm, and edited copies.

The logs are written through the same path as ``cosmos run`` (compile, Session,
Executor). The facts the tests check against (state times, event times, message
counts) are read back with the ``mcap`` package's own reader, not with cosmos's.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mcap.reader import make_reader
from mcap.writer import Writer

from cosmos.commands.run import run_program
from cosmos.runtime.rates import Rates

PROGRAM = """\
MOVE BY (0, 0, 30 mm)
WAIT 0.2 s
MOVE BY (0, 0, -30 mm)
"""
EDITED_LINE = 3
EDITED_PROGRAM = PROGRAM.replace("(0, 0, -30 mm)", "(0, 0, -20 mm)")


def run_to_log(directory: Path, source: str, name: str = "tiny.cos", log_name: str = "run.mcap") -> Path:
    """Write ``source`` to ``directory/name``, run it with default settings, return the log path."""
    program = directory / name
    program.write_text(source)
    log = directory / log_name
    run_program(program, log, Rates(), seed=0)
    return log


def messages(log: Path, topic: str) -> list[tuple[int, bytes]]:
    """``(log_time ns, data)`` of every message on ``topic``, in file order."""
    with open(log, "rb") as stream:
        return [
            (message.log_time, message.data)
            for _, channel, message in make_reader(stream).iter_messages(topics=[topic])
            if channel.topic == topic
        ]


def decoded(log: Path, topic: str) -> list[dict[str, Any]]:
    """The JSON messages on ``topic``."""
    return [json.loads(data) for _, data in messages(log, topic)]


def copy_with_source(
    log: Path,
    out: Path,
    source: str | None = None,
    settings: dict[str, str] | None = None,
    extra: Sequence[tuple[str, int, bytes]] = (),
) -> Path:
    """Copy every record of ``log`` to ``out``, with ``source`` as the program attachment if given,
    ``settings`` overriding entries of the metadata, and ``extra`` messages (topic, log time ns,
    data) added on the existing channels."""
    with open(log, "rb") as stream, open(out, "wb") as sink:
        reader = make_reader(stream)
        summary = reader.get_summary()
        assert summary is not None
        writer = Writer(sink)
        writer.start()
        for schema in summary.schemas.values():
            writer.register_schema(schema.name, schema.encoding, schema.data)
        channel_ids = {
            channel.id: writer.register_channel(
                channel.topic, channel.message_encoding, channel.schema_id, dict(channel.metadata)
            )
            for channel in summary.channels.values()
        }
        for metadata in reader.iter_metadata():
            writer.add_metadata(metadata.name, {**metadata.metadata, **(settings or {})})
        for attachment in reader.iter_attachments():
            writer.add_attachment(
                attachment.create_time,
                attachment.log_time,
                attachment.name,
                attachment.media_type,
                attachment.data if source is None else source.encode(),
            )
        for _, channel, message in reader.iter_messages(log_time_order=False):
            writer.add_message(channel_ids[channel.id], message.log_time, message.data, message.publish_time)
        by_topic = {channel.topic: channel_ids[cid] for cid, channel in summary.channels.items()}
        for topic, t_ns, data in extra:
            writer.add_message(by_topic[topic], t_ns, data, t_ns)
        writer.finish()
    return out


def cosmos(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """Run the ``cosmos`` command line in a fresh process."""
    return subprocess.run(
        [sys.executable, "-m", "cosmos", *args],
        capture_output=True,
        text=True,
        timeout=180,
        env=env if env is not None else dict(os.environ),
    )
