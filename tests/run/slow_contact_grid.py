"""A slow CONTACT from rest (docs/language.md, CONTACT, "Slow approaches start from rest").

Run ``python tests/run/slow_contact_grid.py`` (``--speeds 2,3,5,8``, ``--seeds 0,1,2,3,4,5,ideal``,
``--tool GRIPPER`` or ``PEG``, ``--surface table`` or ``slope``, ``--robot PUMA`` or ``PANDA``,
``--force 5``). Each case moves the tool 20 mm above the surface, then ``CONTACT ... FORCE f
SPEED v TIMEOUT 15 s``. From the run's log (250 Hz) it reports the outcome, the median speed of
the tool point over 100 ms windows from 0.5 s after the approach starts to the touch (the push
past 2 N), the fastest such window, the time to the touch and the peak of the logged push in
the 0.3 s after it, against docs/language.md's bar ``max(1.5 f, f + 5 N)``.
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from pathlib import Path

import numpy as np

import cosmos

WINDOW_TICKS = 25
"""100 ms of the log's state at 250 Hz."""
TOUCH_N = 2.0
"""The approach's touch for FORCE 5 N (half of FORCE if less)."""
APPROACH = {"table": "CONTACT DOWN", "slope": "CONTACT +Z IN slope"}


def program(robot: str, tool: str, surface: str, force_n: float, speed_mmps: float) -> str:
    """The case's program; the CONTACT is its last line."""
    head = "ROBOT PANDA\n" if robot == "PANDA" else ""
    head += "TOOL GRIPPER\n" if tool == "GRIPPER" else ""
    return (
        f"{head}MOVE TO {surface} + (0, 0, 20 mm)\n"
        f"{APPROACH[surface]} FORCE {force_n} N SPEED {speed_mmps} mm/s TIMEOUT 15 s\n"
    )


def measure(source: str, seed: int, ideal: bool) -> str:
    """One case's line of the report."""
    line = source.count("\n")
    with tempfile.TemporaryDirectory() as directory, warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(source, seed=seed, ideal=ideal, log=Path(directory) / "slow.mcap")
    outcome = "ok" if run.ok else str(getattr(run.outcome, "reason", run.outcome))
    state = run.record.state
    on = state.line == line
    t, x, wrench = state.t[on], state.x[on], state.wrench[on]
    if len(t) <= WINDOW_TICKS:
        return f"{outcome}: no approach logged"
    push = np.linalg.norm(wrench[:, :3], axis=1)
    touched = bool(np.any(push > TOUCH_N))
    touch = int(np.argmax(push > TOUCH_N)) if touched else len(t) - 1
    travel = np.linalg.norm(x[WINDOW_TICKS:] - x[:-WINDOW_TICKS], axis=1)
    speeds = travel / (t[WINDOW_TICKS:] - t[:-WINDOW_TICKS]) * 1e3
    start = int(np.searchsorted(t, t[0] + 0.5))
    judged = speeds[start : max(touch - WINDOW_TICKS, start + 1)]
    fastest = float(speeds[: max(touch - WINDOW_TICKS, 1)].max())
    after = (t >= t[touch]) & (t <= t[touch] + 0.3)
    peak = float(push[after].max()) if touched else float("nan")
    return (
        f"{outcome:>4}  median {float(np.median(judged)):5.2f} mm/s  fastest {fastest:5.2f} mm/s  "
        f"touch after {t[touch] - t[0]:5.2f} s  peak {peak:5.2f} N"
    )


def main() -> None:
    """Run the grid and print one line per case."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", default="2,3,5,8", help="SPEEDs in mm/s, comma-separated")
    parser.add_argument("--seeds", default="0,1,2,3,4,5,ideal", help="realistic plant's seeds, 'ideal'")
    parser.add_argument("--tool", default="GRIPPER", choices=("GRIPPER", "PEG"))
    parser.add_argument("--surface", default="table", choices=tuple(APPROACH))
    parser.add_argument("--robot", default="PUMA", choices=("PUMA", "PANDA"))
    parser.add_argument("--force", type=float, default=5.0, help="FORCE in N")
    args = parser.parse_args()
    bar = max(1.5 * args.force, args.force + 5.0)
    print(f"{args.robot} {args.tool} {args.surface} FORCE {args.force} N: bar {bar:.1f} N", flush=True)
    for speed in (float(v) for v in args.speeds.split(",")):
        for seed in args.seeds.split(","):
            ideal = seed == "ideal"
            source = program(args.robot, args.tool, args.surface, args.force, speed)
            print(
                f"{speed:4.1f} mm/s seed {seed:>5}: {measure(source, 0 if ideal else int(seed), ideal)}",
                flush=True,
            )


if __name__ == "__main__":
    main()
