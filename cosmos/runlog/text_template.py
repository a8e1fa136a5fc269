"""Message texts with integer holes, the shape the run log's compiled kernels fill.

A message's text is a fixed template with holes for integers: the vectors of
a state message and the poses of a ``/tf`` message are written as micro-units
with a fixed exponent (``125730e-6`` is 0.125730). :class:`Template` holds the
literal pieces between the holes (:mod:`cosmos.runlog.text_kernel` fills
them); the constants are the limits and outcomes the kernels share with the
writer. No numba here: reading a log imports this module, not the kernels.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Final

import numpy as np

STATE_MICRO_LIMIT: Final = 1e12
"""A state value with ``|v|`` below this (and finite) is written as micro-units; others are not."""

POSE_LIMIT: Final = 1e9
"""A ``/tf`` sample is written only if every coordinate has ``|v|`` below this (and is finite)."""

TIME_LIMIT_S: Final = 1e6
"""The kernel writes ``%.9f`` of times in ``[0, TIME_LIMIT_S)``; the caller formats others."""

INT_DIGITS: Final = 20  # an int64 in decimal, sign included (also bounds a time's "%.9f")
POSE_WIDTH: Final = 7  # x y z, then the quaternion x y z w

STATE_WRITTEN: Final = 0
"""Outcome of a state row: written by the kernel."""
STATE_NOT_EXACT: Final = 1
"""Outcome of a state row: a vector value not finite or not below STATE_MICRO_LIMIT (caller writes it)."""
STATE_TIME_OUTSIDE: Final = 2
"""Outcome of a state row: its time outside ``[0, TIME_LIMIT_S)``, or -0.0 (caller writes it)."""


@dataclass(frozen=True)
class Template:
    """JSON text with integer holes: ``literal 0, int 0, literal 1, ..., int k-1, literal k``.

    Attributes:
        literals: The literal pieces, concatenated, as bytes. # (total,) uint8
        bounds: Where literal ``i`` starts; literal ``i`` is
            ``literals[bounds[i]:bounds[i + 1]]``. # (holes + 2,) int64
    """

    literals: np.ndarray
    bounds: np.ndarray

    @property
    def holes(self) -> int:
        """Number of integers a message takes."""
        return len(self.bounds) - 2

    @property
    def max_bytes(self) -> int:
        """An upper bound on the length of one message."""
        return len(self.literals) + INT_DIGITS * self.holes

    @classmethod
    def from_format(cls, text: str) -> Template:
        """The template of a ``%``-format string whose only directives are ``%d`` (and ``%%``).

        Raises:
            ValueError: If ``text`` has another directive.
        """
        pieces = text.split("%d")
        for piece in pieces:
            if re.search(r"%[^%]", piece.replace("%%", "")):
                raise ValueError(f"only %d directives are supported, got {piece!r}")
        encoded = [piece.replace("%%", "%").encode() for piece in pieces]
        bounds = np.cumsum([0] + [len(p) for p in encoded], dtype=np.int64)
        literals = np.frombuffer(b"".join(encoded), dtype=np.uint8).copy()
        return cls(literals=literals, bounds=bounds)
