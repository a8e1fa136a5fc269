"""The contact-while-sliding grid of issue 14, item 5: every force x speed x direction x frame.

Run ``python tests/run/slide_grid.py`` (40-100 s on two cores; ``--quick`` for
five representative cases, ``--ideal`` on the ideal plant). Each case is a
program: touch the table with CONTACT DOWN at the force, SLIDE 60 mm at the
speed along the direction, in
the world frame or in a task frame turned 45 deg about z. From the run's own
log it reports, over the slide after its force ramp: the lowest push as a
fraction of the setpoint (must stay above 50 %) and the share of samples within
15 % of it (must be at least 95 %), and the mean speed between the SLIDE's
ramps as a fraction of its SPEED (at least 80 %).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

FORCES_N = (5.0, 12.0, 30.0)
SPEEDS_MMPS = (5.0, 20.0, 50.0)
DIRECTIONS = ("+X", "-Y", "diagonal")
FRAMES = ("world", "turned 45 deg")
DISTANCE_MM = 60.0
FORCE_RAMP_S = 0.25
"""The executor ramps a new force setpoint in over this time; the slide is judged after it."""


@dataclass(frozen=True)
class Case:
    """One slide of the grid."""

    force_n: float
    speed_mmps: float
    direction: str
    frame: str

    @property
    def name(self) -> str:
        """``12 N 20 mm/s -Y turned 45 deg``."""
        return f"{self.force_n:g} N {self.speed_mmps:g} mm/s {self.direction} {self.frame}"

    def program(self) -> str:
        """The program text of the case."""
        turned = self.frame != "world"
        slide_frame = "t90" if (turned and self.direction == "diagonal") else "t45"
        direction = "+X" if self.direction == "diagonal" else self.direction
        slide_in = f" IN {slide_frame}" if (turned or self.direction == "diagonal") else ""
        contact_in = " IN t45" if turned else ""
        return (
            "FRAME t45 = table RPY (0, 0, 45 deg)\n"
            "FRAME t90 = table RPY (0, 0, 90 deg)\n"
            "SPEED 0.2 m/s\n"
            "MOVE TO table + (0, 0, 40 mm)\n"
            f"CONTACT DOWN FORCE {self.force_n:g} N SPEED 20 mm/s TIMEOUT 5 s{contact_in}\n"
            f"SLIDE {direction} BY {DISTANCE_MM:g} mm SPEED {self.speed_mmps:g} mm/s{slide_in}\n"
        )


@dataclass(frozen=True)
class Result:
    """What the log of one case shows."""

    case: Case
    returncode: int
    lowest: float  # lowest push / setpoint after the ramp
    within: float  # share of samples within 15 % of the setpoint
    speed: float  # mean speed between the cruise ramps / SPEED

    @property
    def ok(self) -> bool:
        """Item 5's and item 4's bars."""
        return self.returncode == 0 and self.lowest >= 0.5 and self.within >= 0.95 and self.speed >= 0.8


def run_case(case: Case, directory: Path, ideal: bool = False, servo_hz: float | None = None) -> Result:
    """Run one case in this process (``ideal``: on the ideal plant; ``servo_hz``: at that servo rate)
    and judge it from its log."""
    from cosmos.commands.run import run_program
    from cosmos.osc.motion import cruise_ramp_s
    from cosmos.runlog import read_log
    from cosmos.runtime.rates import Rates

    safe = case.name.replace(" ", "_").replace("/", "")
    program = directory / f"{safe}.cos"
    program.write_text(case.program(), encoding="utf-8")
    log_path = directory / f"{safe}.mcap"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        returncode = run_program(program, log_path, Rates.chosen(servo_hz, None), 0, ideal=ideal)
    record = read_log(log_path)
    slides = [s for s in record.segments if s.kind == "slide"]
    if not slides:
        return Result(case, returncode, 0.0, 0.0, 0.0)
    state = record.state
    mask = state.segment == slides[0].segment
    t, x, push = state.t[mask], state.x[mask], -state.wrench[mask, 2]
    judged = t >= t[0] + FORCE_RAMP_S
    ratio = push[judged] / case.force_n
    speed = case.speed_mmps * 1e-3
    ramp = cruise_ramp_s(speed)  # the SLIDE's first and last ramps are left out
    travel = np.linalg.norm(x - x[0], axis=1)
    cruise = (t >= t[0] + ramp) & (t <= t[0] + DISTANCE_MM * 1e-3 / speed)
    mean_speed = (travel[cruise][-1] - travel[cruise][0]) / (t[cruise][-1] - t[cruise][0])
    return Result(
        case,
        returncode,
        float(ratio.min()),
        float(np.mean(np.abs(ratio - 1.0) <= 0.15)),
        float(mean_speed / speed),
    )


def grid(quick: bool = False) -> list[Case]:
    """The 54 cases, or the representative few the suite keeps."""
    if quick:
        return [Case(*c) for c in QUICK]
    return [Case(f, v, d, fr) for fr in FRAMES for d in DIRECTIONS for f in FORCES_N for v in SPEEDS_MMPS]


QUICK = (
    (5.0, 50.0, "+X", "world"),
    (12.0, 20.0, "-Y", "world"),
    (30.0, 5.0, "diagonal", "world"),
    (5.0, 20.0, "-Y", "turned 45 deg"),
    (12.0, 50.0, "diagonal", "turned 45 deg"),
)
"""Representative cases (``--quick``); the suite keeps two (tests/run/test_run_slide_grid.py)."""


def main(argv: list[str] | None = None) -> int:
    """Run the grid and print one line per case and a summary; exit 1 if any case misses."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only the suite's representative cases")
    parser.add_argument(
        "--ideal", action="store_true", help="on the ideal plant (default: the realistic one)"
    )
    args = parser.parse_args(argv)
    results = []
    with tempfile.TemporaryDirectory() as directory:
        for case in grid(args.quick):
            result = run_case(case, Path(directory), ideal=args.ideal)
            results.append(result)
            print(
                f"{'ok  ' if result.ok else 'MISS'} {case.name:34s} exit {result.returncode}  "
                f"lowest {result.lowest:5.0%}  within 15 % {result.within:6.1%}  speed {result.speed:5.0%}",
                flush=True,
            )
    lowest = min(results, key=lambda r: r.lowest)
    fewest = min(results, key=lambda r: r.within)
    slowest = min(results, key=lambda r: r.speed)
    print(
        f"{sum(r.ok for r in results)}/{len(results)} cases meet the bars; lowest push "
        f"{lowest.lowest:.0%} ({lowest.case.name}), fewest within 15 % {fewest.within:.1%} "
        f"({fewest.case.name}), slowest {slowest.speed:.0%} ({slowest.case.name})"
    )
    return 0 if all(r.ok for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
