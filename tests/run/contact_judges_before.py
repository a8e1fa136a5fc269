"""The CONTACT approach's, the hold's and an INSERT's touch judges as they were in Python (issue 20).

Written out here from the monitor before they were compiled (cosmos.execution.approach_stall,
cosmos.execution.lost_push, cosmos.execution.touch_push): the reference the compiled judges must
agree with, tick for tick (tests/run/test_contact_judges.py).
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np

from cosmos.execution.closing import STALL_PROGRESS_M, STALL_TIME_S
from cosmos.execution.monitor import Outcome, Verdict
from cosmos.plan import TOUCH_THRESHOLD_N, ContactTouch, DepthReached, ForceSettled, SegmentKind


class Inertia:
    """touch_push.ToolInertia as it was."""

    def __init__(self, mass_kg: float, speed_mps: float | None) -> None:
        self.mass_kg = mass_kg if speed_mps is not None and speed_mps > 0.030 else 0.0
        self.speeds: deque[tuple[float, float]] = deque()
        self.pushes: deque[tuple[float, float]] = deque()
        self.total_n = 0.0

    def speed_up(self, speed_mps: float, t_s: float) -> float:
        if not self.mass_kg > 0.0:
            return 0.0
        speeds = self.speeds
        speeds.append((t_s, speed_mps))
        while len(speeds) > 2 and t_s - speeds[1][0] >= 0.005 - 1e-9:
            speeds.popleft()
        then_s, then_mps = speeds[0]
        return max((speed_mps - then_mps) / (t_s - then_s), 0.0) if t_s > then_s else 0.0

    def touched(self, contact_n: float, threshold_n: float, t_s: float) -> bool:
        if not self.mass_kg > 0.0:
            return contact_n > threshold_n
        pushes = self.pushes
        pushes.append((t_s, contact_n))
        self.total_n += contact_n
        while t_s - pushes[0][0] >= 0.005 - 1e-9:
            self.total_n -= pushes.popleft()[1]
        return self.total_n / len(pushes) > threshold_n


class Approach:
    """SegmentMonitor._touch with approach_stall.ApproachStall as they were, and the TIMEOUT after."""

    def __init__(self, monitor: Any, touch: ContactTouch) -> None:
        self.monitor, self.touch = monitor, touch
        self.inertia = Inertia(monitor._tool_mass_kg, monitor.segment.speed_limit_mps)
        speed = monitor.segment.speed_limit_mps
        self.progress = STALL_PROGRESS_M if not speed else min(STALL_PROGRESS_M, 0.25 * speed * STALL_TIME_S)
        self.since_s, self.furthest_m = monitor.start_s, 0.0

    def __call__(self, snap: Any) -> Outcome | None:
        done = self.judge(snap)
        return in_time(self.monitor, snap, done)

    def judge(self, snap: Any) -> Outcome | None:
        dx, dy, dz = direction = tuple(self.touch.direction_world.tolist())
        (fx, fy, fz, _, _, _), (vx, vy, vz, _, _, _) = snap.wrench.tolist(), snap.velocity.tolist()
        push = fx * dx + fy * dy + fz * dz
        met = push - self.inertia.mass_kg * self.inertia.speed_up(vx * dx + vy * dy + vz * dz, snap.t_s)
        if self.inertia.touched(met, self.touch.threshold_n, snap.t_s):
            return Outcome(Verdict.DONE, f"touched: {push:.2f} N along the approach", touched=True)
        x, y, z = snap.position.tolist()
        x0, y0, z0 = self.monitor._start_xyz
        travel = (x - x0) * dx + (y - y0) * dy + (z - z0) * dz
        assert len(direction) == 3
        if travel >= self.touch.max_travel_m - 1e-3:
            return Outcome(Verdict.FAILED, f"found no contact within {self.touch.max_travel_m * 1e3:.0f} mm")
        if travel > self.furthest_m + self.progress:
            self.furthest_m, self.since_s = travel, snap.t_s
            return None
        if snap.t_s - self.since_s < STALL_TIME_S:
            return None
        if push >= 0.5:
            why = f"touched: stopped against it {push:.2f} N along the approach for {STALL_TIME_S:g} s"
            return Outcome(Verdict.DONE, why, touched=True)
        return Outcome(
            Verdict.FAILED,
            f"stopped {max(travel, 0.0) * 1e3:.1f} mm along its approach without touching "
            f"({push:.2f} N along it for {STALL_TIME_S:g} s): {self.monitor.stall_cause()}",
        )


class Hold:
    """SegmentMonitor._force_settled with lost_push.LostPush as they were, and the TIMEOUT after."""

    def __init__(self, monitor: Any, settled: ForceSettled) -> None:
        segment = monitor.segment
        self.monitor, self.settled, self.segment = monitor, settled, segment
        push = np.asarray(segment.frame_rotation, dtype=float).dot(np.asarray(segment.force_setpoint[:3]))
        size = float(np.linalg.norm(push))
        self.push = (0.0, 0.0, 0.0) if not size > 0.0 else tuple((push / size).tolist())
        self.at = self.pressed_at = monitor._start_xyz
        self.since_s, self.settled_since = monitor.start_s, None
        self.touching_n = min(TOUCH_THRESHOLD_N, 0.5 * size)
        self.contact = segment.kind is SegmentKind.CONTACT_HOLD
        rows_t = monitor._rotation_t.tolist()
        setpoints = np.asarray(segment.force_setpoint, dtype=float).tolist()
        axes = monitor._force_axes
        self.terms = [(3 * (i // 3), *rows_t[i % 3], setpoints[i]) for i in range(6) if axes[i]]

    def __call__(self, snap: Any) -> Outcome | None:
        return in_time(self.monitor, snap, self.judge(snap))

    def judge(self, snap: Any) -> Outcome | None:
        x, y, z = snap.position.tolist()
        (nx, ny, nz), (x0, y0, z0) = self.push, self.at
        if (x - x0) * nx + (y - y0) * ny + (z - z0) * nz > 0.001:
            self.at, self.since_s, self.settled_since = (x, y, z), snap.t_s, None
        if self.contact:
            fx, fy, fz, _, _, _ = snap.wrench.tolist()
            free = 0.0
            if math.sqrt(fx * fx + fy * fy + fz * fz) >= self.touching_n:
                self.pressed_at = (x, y, z)
            else:
                (x0, y0, z0) = self.pressed_at
                free = (x - x0) * nx + (y - y0) * ny + (z - z0) * nz
            if free > 0.015:
                return Outcome(
                    Verdict.FAILED,
                    f"lost contact: the tool ran on {free * 1e3:.1f} mm along its push touching nothing "
                    f"(under {self.touching_n:g} N) at {snap.t_s:.2f} s",
                )
        settled, elapsed = self.settled, snap.t_s - self.since_s
        wrench, worst = snap.wrench.tolist(), 0.0
        for at, rx, ry, rz, setpoint in self.terms:
            worst = max(worst, abs(rx * wrench[at] + ry * wrench[at + 1] + rz * wrench[at + 2] - setpoint))
        if worst <= settled.tolerance_n:
            if self.settled_since is None:
                self.settled_since = snap.t_s
            if snap.t_s - self.settled_since >= settled.settle_time_s:
                return Outcome(Verdict.DONE, "force settled")
        else:
            self.settled_since = None
        if elapsed >= settled.max_time_s:
            setpoint = float(np.max(np.abs(self.segment.force_setpoint[self.monitor._force_axes])))
            if worst <= 0.5 * setpoint:
                return Outcome(
                    Verdict.DONE,
                    f"contact held, force within {worst:.1f} N of its setpoint but not settled "
                    f"to {settled.tolerance_n:g} N in {settled.max_time_s:g} s",
                )
            return Outcome(Verdict.FAILED, f"force did not settle within {settled.max_time_s:g} s")
        return None


class InsertTouch:
    """An INSERT approach's touch in SegmentMonitor._depth as it was: the touch, or None to go on."""

    def __init__(self, monitor: Any, depth: DepthReached) -> None:
        self.depth, self.inertia = depth, Inertia(monitor._tool_mass_kg, monitor.segment.speed_limit_mps)

    def __call__(self, snap: Any) -> Outcome | None:
        dx, dy, dz = self.depth.direction_world.tolist()
        (fx, fy, fz, _, _, _), (vx, vy, vz, _, _, _) = snap.wrench.tolist(), snap.velocity.tolist()
        push = math.sqrt(fx * fx + fy * fy + fz * fz)
        inertia = self.inertia.mass_kg * self.inertia.speed_up(vx * dx + vy * dy + vz * dz, snap.t_s)
        fx, fy, fz = fx - inertia * dx, fy - inertia * dy, fz - inertia * dz
        assert self.depth.touch_n is not None
        if self.inertia.touched(math.sqrt(fx * fx + fy * fy + fz * fz), self.depth.touch_n, snap.t_s):
            return Outcome(Verdict.DONE, f"touched: {push:.2f} N", touched=True)
        return None


def in_time(monitor: Any, snap: Any, done: Outcome | None) -> Outcome | None:
    """SegmentMonitor._complete_in_time's TIMEOUT after the ending, when the judge is alone (no UNTIL)."""
    if done is None and monitor.segment.until is None and snap.t_s >= monitor._deadline_s:
        return monitor._timed_out(snap)
    return done
