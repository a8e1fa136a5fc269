"""The MCAP run log: writing it during a run, reading it back, recovering cut files.

See docs/log-format.md for the format.
"""

from cosmos.runlog.reader import EventRecord, RunRecord, SegmentRecord, read_log
from cosmos.runlog.recover import recover
from cosmos.runlog.scene import Box, Color, Cylinder, Sphere
from cosmos.runlog.schemas import EventKind
from cosmos.runlog.writer import RunLog, default_log_path

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
