"""The MCAP run log: writing it during a run, reading it back, recovering cut files.

See docs/log-format.md for the format. The names below are loaded when first
used: a run, which only writes, does not import the reader and the recovery
(the ``mcap`` package and its decoders).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from cosmos.runlog.reader import EventRecord, RunRecord, SegmentRecord, read_log
    from cosmos.runlog.recover import recover
    from cosmos.runlog.scene import Box, Color, Cylinder, Sphere
    from cosmos.runlog.schemas import EventKind
    from cosmos.runlog.writer import RunLog, default_log_path

_HOMES = {
    "Box": "scene",
    "Color": "scene",
    "Cylinder": "scene",
    "EventKind": "schemas",
    "EventRecord": "reader",
    "RunLog": "writer",
    "RunRecord": "reader",
    "SegmentRecord": "reader",
    "Sphere": "scene",
    "default_log_path": "writer",
    "read_log": "reader",
    "recover": "recover",
}
"""Each public name's module in this package."""

__all__ = [
    "Box",
    "Color",
    "Cylinder",
    "EventKind",
    "EventRecord",
    "RunLog",
    "RunRecord",
    "SegmentRecord",
    "Sphere",
    "default_log_path",
    "read_log",
    "recover",
]


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{home}"), name)
    globals()[name] = value
    return value
