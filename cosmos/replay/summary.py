"""The text summary of a run log: what ran, for how long, and what each statement did."""

from __future__ import annotations

import math
from collections.abc import Sequence

from cosmos.execution.wording import short_context
from cosmos.replay.timeline import StatementRun
from cosmos.runlog.reader import RunRecord

_STATEMENT_WIDTH = 44


def shorten(text: str, width: int) -> str:
    """``text`` on one line, cut to ``width`` characters with an ellipsis."""
    flat = " ".join(text.split())
    return flat if len(flat) <= width else flat[: width - 1] + "…"


def _newtons(value: float) -> str:
    return "-" if math.isnan(value) else f"{value:.1f} N"


def _size(n_bytes: int) -> str:
    return f"{n_bytes / 1024:.1f} KiB" if n_bytes < 1024 * 1024 else f"{n_bytes / 2**20:.2f} MiB"


def _chunks(record: RunRecord) -> str:
    """``12 chunks, zstd (1.90 MiB of messages compressed to 417.0 KiB, 22 %)`` or the like."""
    if not record.chunks:
        return "no chunks"
    parts = []
    for name, (count, packed, unpacked) in sorted(record.chunks.items()):
        ratio = f", {100 * packed / unpacked:.0f} %" if unpacked else ""
        parts.append(f"{count} chunks {name} ({_size(unpacked)} to {_size(packed)}{ratio})")
    return "; ".join(parts)


def _channel_table(record: RunRecord) -> list[str]:
    """The channels as ``mcap info`` lists them: topic, messages, rate, schema and encoding."""
    channels = record.channels
    if not channels:  # a record made without channel details: the counts only
        width = max((len(topic) for topic in record.message_counts), default=0)
        rows = sorted(record.message_counts.items())
        return ["channels"] + [f"  {topic:<{width}}  {count:>8} messages" for topic, count in rows]
    width = max(len(c.topic) for c in channels)
    schema_width = max(len(c.schema) for c in channels)
    lines = [f"channels  ({len(channels)})"]
    for c in channels:
        rate = f"{c.rate_hz:8.1f} Hz" if c.rate_hz else f"{'-':>8}   "
        lines.append(
            f"  {c.topic:<{width}}  {c.messages:>8} msgs  {rate}  {c.schema:<{schema_width}}  [{c.encoding}]"
        )
    return lines


def _with_origin(reason: str, context: str) -> str:
    """A row's reason led by where its statement came from: ``[pass 2/2 @6 > probe @7] found no ...``."""
    return f"[{short_context(context)}] {reason}" if context else reason


def format_summary(record: RunRecord, timeline: Sequence[StatementRun]) -> str:
    """Header (program, versions, rates, duration, channels) and the statement timeline."""
    meta = record.metadata
    lines = [f"log       {record.path}"]
    program = meta.get("program", "?")
    if record.source is not None:
        count = len(record.source.splitlines())
        program += f"  (source attached as {record.source_name}, {count} lines)"
    lines.append(f"program   {program}")
    lines.append(
        f"cosmos    {meta.get('cosmos_version', '?')}   model {meta.get('model', '?')}"
        f"   seed {meta.get('seed', '?')}"
    )
    servo, param, state = (meta.get(f"{name}_hz", "?") for name in ("servo", "param", "state"))
    lines.append(f"rates     servo {servo} Hz, parameters {param} Hz, state {state} Hz")
    lines.append(f"duration  {record.end_time:.3f} s of simulated time")
    lines.append(f"file      {_size(record.total_bytes)}, {_chunks(record)}")
    lines.extend(_channel_table(record))
    if record.truncated:
        lines.append(
            f"WARNING: this log was cut short (no footer): {_size(record.readable_bytes)} of "
            f"{_size(record.total_bytes)} readable, up to t = {record.end_time:.3f} s. "
            f"`cosmos replay {record.path} --recover OUT.mcap` writes a complete copy."
        )
    lines.append("")
    if not timeline:
        lines.append("no statement events in this log")
        return "\n".join(lines)
    lines.append(
        f"{'line':>5}  {'statement':<{_STATEMENT_WIDTH}}  {'start s':>8}  {'end s':>8}  "
        f"{'outcome':<10}  {'peak |F|':>9}  {'final |F|':>9}  reason"
    )
    for run in timeline:
        indent = "  " * run.depth
        text = indent + shorten(run.statement, _STATEMENT_WIDTH - len(indent))
        lines.append(
            f"{run.line:>5}  {text:<{_STATEMENT_WIDTH}}  {run.start:>8.3f}  {run.end:>8.3f}  "
            f"{run.outcome:<10}  {_newtons(run.peak_force):>9}  {_newtons(run.final_force):>9}  "
            f"{_with_origin(run.reason, run.context)}".rstrip()
        )
        for note in run.notes:
            lines.append(f"{'':>5}  {'':<{_STATEMENT_WIDTH}}  - {note}")
    return "\n".join(lines)
