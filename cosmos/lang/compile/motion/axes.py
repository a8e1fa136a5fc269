"""The per-axis setup of a motion segment, and the helpers its messages use.

The diagonal of the seed's selection matrix Omega (motion) and its complement
(force), the force setpoint, stiffness and damping of each task axis, in the
segment's task frame (:class:`Axes`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos.lang import ast
from cosmos.lang.compile.state import HeldContact
from cosmos.rotations import readonly

ALIGNED_COS = math.cos(math.radians(1.0))
"""A contact direction within 1 degree of a task axis counts as along it."""

AXIS_NAMES = tuple(axis.name for axis in ast.Axis)


@dataclass(frozen=True)
class Axes:
    """Per-axis setup of a segment in its task frame."""

    motion: np.ndarray  # (6,) bool
    force: np.ndarray  # (6,) float
    stiffness: tuple[float | None, ...]
    damping: tuple[float | None, ...]
    all_motion: bool  # motion.all()


NO_FORCES: dict[int, float] = {}  # never changed
NO_FREE: set[int] = set()  # never changed


def _all_motion() -> Axes:
    """Every axis under motion control (no COMPLY, no force); its arrays are read-only."""
    motion = np.ones(6, dtype=bool)
    motion.flags.writeable = False
    return Axes(motion, readonly(np.zeros(6)), (None,) * 6, (None,) * 6, True)


ALL_MOTION = _all_motion()


def held_since(contact: HeldContact | None) -> str:
    """``"the contact held since line 3"``, for messages."""
    return f"the contact held since line {contact.span.line}" if contact else ""


def axis_list(axes: list[int] | set[int]) -> str:
    """``"X RY"``: the names of axes given by index."""
    return " ".join(AXIS_NAMES[i] for i in sorted(axes))


def vector_text(vector: np.ndarray) -> str:
    """``"(0, 0, -1)"``: a vector for messages."""
    return "(" + ", ".join(f"{v:.3g}" if abs(v) > 1e-12 else "0" for v in vector) + ")"
