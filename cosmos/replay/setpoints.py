"""What a run was asked to do, as plotted beside what it did: goals, force setpoints, orientation.

Pure functions of the logged segments and states (docs/log-format.md for the
conventions): a segment's goal holds from its start to the next segment's; its
force setpoint, given in the task frame, applies along the force-controlled
axes only and is drawn in world axes, like the measured wrench.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from cosmos.runlog.reader import SegmentRecord


@dataclass(frozen=True)
class Step:
    """A value held over a time interval.

    Attributes:
        start: Start [s].
        stop: End [s].
        value: The value, world axes. # (3,)
    """

    start: float
    stop: float
    value: np.ndarray


def _intervals(segments: Sequence[SegmentRecord], end: float) -> list[tuple[SegmentRecord, float, float]]:
    ordered = sorted(segments, key=lambda s: s.t)
    stops = [s.t for s in ordered[1:]] + [max(end, ordered[-1].t if ordered else end)]
    return [(s, s.t, stop) for s, stop in zip(ordered, stops, strict=True)]


def goal_steps(segments: Sequence[SegmentRecord], end: float) -> list[Step]:
    """Each segment's goal position [m] (world) over the segment; segments without a goal are skipped."""
    return [
        Step(start, stop, np.array(segment.goal[:3], dtype=float))
        for segment, start, stop in _intervals(segments, end)
        if segment.goal is not None
    ]


def force_setpoint_world(segment: SegmentRecord) -> np.ndarray | None:
    """The force to apply [N] in world axes, along the force-controlled translational axes; None if none.

    ``R(frame) @ (f_task * s')`` with ``s'`` 1 on force-controlled axes (the seed's selection
    matrix complement, eq. 17-18): motion-controlled axes contribute nothing.
    """
    selected = np.array([1.0 - a for a in segment.motion_axes[:3]])
    if not selected.any():
        return None
    w, x, y, z = segment.frame
    rotation = Rotation.from_quat([x, y, z, w]).as_matrix()
    return rotation @ (np.array(segment.force_setpoint[:3], dtype=float) * selected)


def force_steps(segments: Sequence[SegmentRecord], end: float) -> list[Step]:
    """:func:`force_setpoint_world` of each force-controlled segment over the segment."""
    steps = []
    for segment, start, stop in _intervals(segments, end):
        force = force_setpoint_world(segment)
        if force is not None:
            steps.append(Step(start, stop, force))
    return steps


def rpy_degrees(quat_wxyz: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw [deg] about the fixed x, y, z axes (the language's RPY), unwrapped in time.

    Args:
        quat_wxyz: Orientations, w x y z; rows with a non-finite value give NaN. # (n, 4)

    Returns:
        Angles, continuous across +-180 deg. # (n, 3)
    """
    out = np.full((len(quat_wxyz), 3), np.nan)
    finite = np.isfinite(quat_wxyz).all(axis=1) & (np.linalg.norm(np.nan_to_num(quat_wxyz), axis=1) > 0)
    if finite.any():
        q = quat_wxyz[finite]
        angles = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_euler("xyz")
        out[finite] = np.degrees(np.unwrap(angles, axis=0))
    return out
