"""A synthetic run written with RunLog: known signals, statements, segments and events.

The signals are closed-form functions of time, so tests compute what the log
must hold (forces, times, outcomes) from them rather than from the log.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from cosmos.runlog import Box, Cylinder, RunLog, Sphere

STATE_HZ = 250.0
PROGRAM = """\
# synthetic peg-in-hole
MOVE TO hole + (0, 0, 80 mm)
CONTACT DOWN FORCE 10 N
SLIDE +X BY 20 mm FORCE 10 N
INSERT DOWN DEPTH 30 mm FORCE 15 N
MOVE BY (0, 0, 100 mm)
"""


@dataclass(frozen=True)
class Statement:
    line: int
    text: str
    start: float
    end: float
    outcome: str
    reason: str


STATEMENTS = (
    Statement(2, "MOVE TO hole + (0, 0, 80 mm)", 0.0, 1.0, "done", ""),
    Statement(3, "CONTACT DOWN FORCE 10 N", 1.0, 2.0, "done", ""),
    Statement(4, "SLIDE +X BY 20 mm FORCE 10 N", 2.0, 3.0, "stopped", "DISTANCE > 20 mm"),
    Statement(5, "INSERT DOWN DEPTH 30 mm FORCE 15 N", 3.0, 4.0, "failed", "jammed at 10 mm"),
)
TOUCH_T = 1.5  # the CONTACT statement touches the surface here
END_T = 4.0

# (start time, line, kind, motion_axes): CONTACT is an approach then a force-controlled hold.
SEGMENTS = (
    (0.0, 2, "move", (1, 1, 1, 1, 1, 1)),
    (1.0, 3, "contact", (1, 1, 1, 1, 1, 1)),
    (TOUCH_T, 3, "contact", (1, 1, 0, 1, 1, 1)),
    (2.0, 4, "slide", (1, 1, 0, 1, 1, 1)),
    (3.0, 5, "insert", (0, 0, 0, 0, 0, 1)),
)
FORCE_CONTROLLED = ((TOUCH_T, END_T),)


def position(t: float) -> np.ndarray:
    """Tool position [m]."""
    x = 0.5 + 0.02 * min(max(t - 2.0, 0.0), 1.0)
    if t < 1.0:
        z = 0.30 - 0.20 * t
    elif t < TOUCH_T:
        z = 0.10 - 0.04 * (t - 1.0)
    elif t < 3.0:
        z = 0.08
    else:
        z = 0.08 - 0.01 * min(t - 3.0, 1.0)
    return np.array([x, 0.1 + 0.002 * math.sin(3.0 * t), z])


def force(t: float) -> np.ndarray:
    """Force the tool applies to the environment [N], world axes."""
    if t < TOUCH_T:
        return np.zeros(3)
    fx = 1.0 if 2.0 <= t < 3.0 else 0.0
    fz = -10.0 if t < 3.0 else -15.0 - 10.0 * (t - 3.0)
    return np.array([fx, 0.0, fz])


def state_args(k: int) -> dict[str, Any]:
    """Keyword arguments of RunLog.state for sample k."""
    t = k / STATE_HZ
    q = np.array([math.sin(t + j) for j in range(6)])
    line = next((s.line for s in reversed(STATEMENTS) if s.start <= t), 2)
    segment = max(i for i, seg in enumerate(SEGMENTS) if seg[0] <= t)
    return {
        "t": t,
        "q": q,
        "qd": np.cos(q),
        "tau": 10.0 * q,
        "x": position(t),
        "quat": np.array([0.0, 1.0, 0.0, 0.0]),
        "v": np.array([0.0, 0.0, -0.2, 0.0, 0.0, 0.0]) if t < 1.0 else np.zeros(6),
        "wrench": np.concatenate([force(t), [0.0, 0.0, 0.1 * math.sin(t)]]),
        "segment": segment,
        "line": line,
    }


def segment_args(index: int) -> dict[str, Any]:
    t, line, kind, axes = SEGMENTS[index]
    statement = next(s.text for s in STATEMENTS if s.line == line)
    fz = 10.0 if kind in ("contact", "slide") and axes[2] == 0 else 15.0 if kind == "insert" else 0
    return {
        "segment": index,
        "line": line,
        "statement": statement,
        "kind": kind,
        "frame": (0.0, 1.0, 0.0, 0.0),
        "motion_axes": axes,
        "force_setpoint": (0.0, 0.0, fz, 0.0, 0.0, 0.0),
        "stiffness": tuple(400.0 * a for a in axes),
        "damping": (40.0, 40.0, 40.0, 4.0, 4.0, 4.0),
        "goal": (0.5, 0.1, 0.1) if kind == "move" else None,
        "speed_limit": 0.2 if kind == "move" else 0.01,
        "timeout": 10.0 if kind == "insert" else None,
    }


@dataclass
class WrittenRun:
    """What write_run wrote, and the file size at each flush."""

    path: Path
    states: int = 0
    flushes: list[tuple[int, int]] = field(default_factory=list)  # (file bytes, states)


def open_log(path: Path, chunk_size: int = 4 * 1024 * 1024) -> RunLog:
    """The synthetic run's log; it flushes only when told, so the file size at each flush is known."""
    return RunLog(
        path,
        program="programs/peg.cos",
        source=PROGRAM,
        servo_hz=1000,
        param_hz=200,
        state_hz=STATE_HZ,
        model="puma560",
        seed=7,
        metadata={"scene": "workcell"},
        chunk_size=chunk_size,
        flush_every_s=math.inf,
    )


def write_run(log: RunLog, written: WrittenRun, close: bool = True) -> WrittenRun:
    """Write the synthetic run into ``log``, flushing at every statement boundary."""
    log.scene(
        0.0,
        add=[
            Box("table", (0.5, 0.0, -0.025), (0.8, 1.2, 0.05)),
            Cylinder("post", (0.4, -0.2, 0.3), 0.04, 0.6),
            Sphere("ball", (0.4, 0.25, 0.5), 0.06),
        ],
    )
    n_samples = int(END_T * STATE_HZ) + 1
    boundaries = {round(s.start * STATE_HZ): s for s in STATEMENTS}
    segment_starts = {round(seg[0] * STATE_HZ): i for i, seg in enumerate(SEGMENTS)}
    ends = {round(s.end * STATE_HZ): s for s in STATEMENTS}
    for k in range(n_samples):
        t = k / STATE_HZ
        if k in ends and k > 0:
            s = ends[k]
            log.event(t, s.outcome, line=s.line, statement=s.text, reason=s.reason)
        if k in boundaries:
            s = boundaries[k]
            log.event(t, "start", line=s.line, statement=s.text)
        if k in segment_starts:
            log.segment(t, **segment_args(segment_starts[k]))
        if k in boundaries or k == n_samples - 1:
            # as the runtime does: flush once a statement has been announced
            log.flush()
            written.flushes.append((os.path.getsize(written.path), written.states))
        if k == round(TOUCH_T * STATE_HZ):
            log.event(t, "contact", line=3, statement=STATEMENTS[1].text, reason="touched")
        if k == round(3.5 * STATE_HZ):
            log.scene(t, remove=["ball"])
        log.state(**state_args(k))
        written.states += 1
        if k % 10 == 0:
            log.transforms(t, np.tile(position(t), (7, 1)), np.tile([1.0, 0, 0, 0], (7, 1)))
    if close:
        log.close()
    return written


def write_synthetic_run(path: Path, chunk_size: int = 4 * 1024 * 1024) -> WrittenRun:
    return write_run(open_log(path, chunk_size), WrittenRun(path))
