"""INSERT ... SEARCH from where a user starts it: patterns, radii, pitches and offsets (issue 14).

Each case is a program as a user writes it from docs/language.md: move above the hole at a
lateral error, ``CONTACT DOWN``, then ``INSERT DOWN ... SEARCH pattern RADIUS r PITCH p``, on
the realistic plant (seeds 0-3) and the ideal one. A case succeeds when its INSERT is done
with the tip at its DEPTH below the mouth on the hole's axis (the mouth and the axis as
tests/run/run_support.py writes them from docs/workcell.md, not from the code under test).
It prints each run and the count of successes; the wrist's peak during the INSERT too.

Run::

    python tests/run/search_grid.py            # about 10 minutes on 2 cores (--jobs 2)
    python tests/run/search_grid.py --only 5   # the cases 5 mm off
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run_support import HOLE_MOUTH_M  # noqa: E402


@dataclass(frozen=True)
class Case:
    """One search: where it starts, its pattern, and the pushes of the CONTACT and the INSERT."""

    off_mm: float
    bearing_deg: float
    pattern: str
    radius_mm: float
    pitch_mm: float
    contact_n: float = 6.0
    insert_n: float = 12.0
    contact: bool = True
    panda: bool = False
    """CONTACT DOWN first from 5 mm above; else the INSERT's own approach from 2 mm above."""

    @property
    def offset_mm(self) -> tuple[float, float]:
        """The start's lateral error, world x and y [mm]."""
        b = math.radians(self.bearing_deg)
        return self.off_mm * math.cos(b), self.off_mm * math.sin(b)

    def program(self, depth_mm: float = 20.0) -> str:
        """The user's program: above the hole at the error, CONTACT DOWN, INSERT with SEARCH."""
        dx, dy = self.offset_mm
        length = math.pi * self.radius_mm**2 / self.pitch_mm
        if self.pattern == "LISSAJOUS":
            length *= 1.6
        timeout = math.ceil(length / 10.0 + 15.0)
        start = (
            f"MOVE TO hole + ({dx:.2f} mm, {dy:.2f} mm, 5 mm)\n"
            f"CONTACT DOWN FORCE {self.contact_n:g} N SPEED 5 mm/s TIMEOUT 5 s\n"
            if self.contact
            else f"MOVE TO hole + ({dx:.2f} mm, {dy:.2f} mm, 2 mm)\nWAIT 0.1 s\n"
        )
        return (
            ("ROBOT panda\n" if self.panda else "")
            + "SPEED 0.2 m/s\n"
            + start
            + f"INSERT DOWN DEPTH {depth_mm:g} mm FORCE {self.insert_n:g} N SEARCH {self.pattern} "
            f"RADIUS {self.radius_mm:g} mm PITCH {self.pitch_mm:g} mm TIMEOUT {timeout} s\n"
            "MOVE BY (0, 0, 50 mm) SPEED 30 mm/s\n"
        )


CASES = (
    Case(0.0, 0.0, "SPIRAL", 4.0, 2.0, contact=False),
    Case(0.0, 0.0, "LISSAJOUS", 4.0, 2.0, 8.0, 15.0, contact=False),
    Case(3.0, 20.0, "SPIRAL", 6.0, 3.0, contact=False),
    Case(2.5, 120.0, "SPIRAL", 4.0, 2.0, 8.0, 15.0),
    Case(2.5, 300.0, "LISSAJOUS", 4.0, 2.0),
    Case(5.0, 143.1, "LISSAJOUS", 8.0, 3.0),  # the user's (-4 mm, 3 mm)
    Case(5.0, 30.0, "SPIRAL", 8.0, 3.0, 8.0, 15.0),
    Case(5.0, 250.0, "SPIRAL", 8.0, 2.0),
    Case(8.0, 200.0, "SPIRAL", 12.0, 4.0),
    Case(8.0, 60.0, "LISSAJOUS", 12.0, 4.0, 8.0, 15.0),
    Case(12.0, 315.0, "SPIRAL", 16.0, 5.0, 8.0, 15.0),
    Case(12.0, 100.0, "LISSAJOUS", 16.0, 5.0),
    Case(16.0, 0.0, "SPIRAL", 20.0, 6.0, 8.0, 15.0),
    Case(16.0, 225.0, "LISSAJOUS", 20.0, 6.0),
    Case(16.0, 170.0, "SPIRAL", 20.0, 4.0),
    Case(7.8, -50.2, "SPIRAL", 12.0, 3.0, 8.0, panda=True),  # the lead's, on the Panda
)
PLANTS = ((0, False), (1, False), (2, False), (3, False), (0, True))
"""(seed, ideal): the realistic plant's seeds 0-3, then the ideal plant."""
DEPTH_MM = 20.0
ON_AXIS_M = 1.5e-3
"""The tip within this of the hole's axis at its depth (tests/run/search_seeds.py)."""


@dataclass(frozen=True)
class Result:
    """What a run's log shows of its INSERT."""

    ok: bool
    outcome: str
    depth_mm: float
    off_axis_mm: float
    peak_n: float
    tilt_deg: float
    """The tool's largest tilt from upright after the find [deg]."""


def run_case(case: Case, seed: int, ideal: bool) -> Result:
    """Run one case in this process, read its log."""
    import warnings

    import cosmos
    from cosmos.runlog import read_log

    warnings.simplefilter("ignore", cosmos.CosmosWarning)
    with tempfile.TemporaryDirectory() as name:
        log = Path(name) / "run.mcap"
        run = cosmos.run(case.program(DEPTH_MM), seed=seed, ideal=ideal, log=log)
        record = read_log(log)
    state = record.state
    lines = case.program(DEPTH_MM).splitlines()
    line = 1 + next(i for i, text in enumerate(lines) if text.startswith("INSERT"))
    events = [e for e in record.events if e.line == line]
    ends = [e for e in events if e.kind in ("done", "failed", "stopped")]
    found = [e.t for e in events if e.kind == "found"]
    during = state.line == line
    x = state.x[during]
    if not len(x):
        return Result(False, str(run.outcome).splitlines()[0], 0.0, 0.0, 0.0, 0.0)
    deepest = int(np.argmin(x[:, 2]))
    depth = float(HOLE_MOUTH_M[2] - x[deepest, 2])
    off = float(np.hypot(*(x[deepest, :2] - HOLE_MOUTH_M[:2])))
    peak = float(np.linalg.norm(state.wrench[during, :3], axis=1).max())
    w, qx, qy, _ = state.quat[during].T
    tilt = np.degrees(np.arccos(np.clip(np.abs(1 - 2 * (qx * qx + qy * qy)), 0.0, 1.0)))
    after = state.t[during] >= (found[0] if found else np.inf)
    outcome = f"{ends[-1].kind}: {ends[-1].reason}" if ends else "missing"
    below = DEPTH_MM - (0.0 if case.contact else 2.0)  # the INSERT's DEPTH counts from its start
    ok = bool(ends) and ends[-1].kind == "done" and depth > (below - 1.0) * 1e-3 and off < ON_AXIS_M
    return Result(ok, outcome, depth * 1e3, off * 1e3, peak, float(tilt[after].max()) if after.any() else 0.0)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", type=float, default=None, help="only the cases this far off [mm]")
    parser.add_argument("--jobs", type=int, default=2, help="processes")
    parser.add_argument("--ideal-only", action="store_true", help="only the ideal plant")
    args = parser.parse_args()
    cases = [c for c in CASES if args.only is None or c.off_mm == args.only]
    plants = [(seed, ideal) for seed, ideal in PLANTS if ideal or not args.ideal_only]
    jobs = [(case, seed, ideal) for case in cases for seed, ideal in plants]
    with ProcessPoolExecutor(args.jobs) as pool:
        results = list(pool.map(run_case, *zip(*jobs, strict=True)))
    wins, peaks = 0, []
    for (case, seed, ideal), result in zip(jobs, results, strict=True):
        wins += result.ok
        peaks.append(result.peak_n)
        plant = "ideal" if ideal else f"seed {seed}"
        dx, dy = case.offset_mm
        print(
            f"({dx:6.2f}, {dy:6.2f}) mm {case.pattern:9s} R {case.radius_mm:g} P {case.pitch_mm:g} "
            f"{case.insert_n:g} N {plant:7s}: {'ok  ' if result.ok else 'FAIL'} depth "
            f"{result.depth_mm:5.1f} mm, {result.off_axis_mm:4.2f} mm off, peak {result.peak_n:5.1f} N, "
            f"tilt after the find {result.tilt_deg:4.1f} deg; {result.outcome}"
        )
    p = np.percentile(peaks, (50, 95, 100))
    print(
        f"{wins} of {len(jobs)} inserted; peak force median / 95 % / max "
        f"{p[0]:.1f} / {p[1]:.1f} / {p[2]:.1f} N"
    )
    return 0 if wins == len(jobs) else 1


if __name__ == "__main__":
    raise SystemExit(main())
