"""What the log reader accepts: caps on sizes and counts that bound its time and memory.

A run log is untrusted input (a file can come from anywhere). The reader
refuses a file past any of these caps with one line naming the file and the
cap, instead of reading without end. Each cap is far above what a run writes:
an hour of a run at the default rates is about 1.1 million messages and 900 MB
of message text in about 100 MB of file. The caps on counts bound the reader's
time (a few seconds a million messages) and memory.
"""

from __future__ import annotations

from typing import Final

MAX_LOG_BYTES: Final = 2 * 1024**3
"""Largest log file read [bytes]."""

MAX_CHUNK_BYTES: Final = 64 * 1024**2
"""Largest decompressed MCAP chunk [bytes] (the writer closes a chunk at 256 KiB)."""

MAX_DECOMPRESSED_BYTES: Final = 2 * 1024**3
"""Largest sum of decompressed chunk sizes over a file [bytes]."""

MAX_RECORDS: Final = 3_000_000
"""Most MCAP records read from a file, those inside chunks included."""

MAX_MESSAGES: Final = 2_000_000
"""Most messages read from a file, all channels together."""

MAX_STATEMENT_MESSAGES: Final = 200_000
"""Most ``/cosmos/segment`` messages, and most ``/cosmos/event`` messages, in a file."""

MAX_MESSAGE_BYTES: Final = 1024**2
"""Largest message on a cosmos channel (``/cosmos/...``) [bytes]; a state message is about 600."""

MAX_SCENE_MESSAGE_BYTES: Final = 16 * 1024**2
"""Largest ``/scene`` message [bytes]."""

MAX_ATTACHMENT_BYTES: Final = 64 * 1024**2
"""Largest attachment [bytes]."""

MAX_METADATA_ENTRIES: Final = 1000
"""Most ``name: value`` pairs in one metadata record, and most metadata records."""

MAX_TEXT_CHARS: Final = 65536
"""Longest text field read from a log: a statement, a reason, a metadata value [characters]."""

MAX_LINE: Final = 10_000_000
"""Largest source line number a message may name."""

MAX_SEGMENT: Final = 1_000_000_000
"""Largest segment index a message may name."""

MAX_TIME_S: Final = 1e7
"""Largest simulated time a message may carry [s] (about 116 days)."""
