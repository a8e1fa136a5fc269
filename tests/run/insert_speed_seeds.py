"""INSERT's peak speed along its axis, seed by seed, on both plants (issue 14, item 4).

The program and the measure are tests/run/test_run_insert_speed.py's: from 2 mm above and
2 mm off the hole, ``INSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY X Y RX RY SPEED v``; the peak
of MuJoCo's tool point's travel over five log samples (20 ms), approach included, against
the limit (SPEED, or the default 20 mm/s). Run every SPEED with seeds 0-4 (the README's
Measured table)::

    python tests/run/insert_speed_seeds.py            # about 4 minutes on 2 cores
    python tests/run/insert_speed_seeds.py --ideal
    python tests/run/insert_speed_seeds.py --speeds 3,8   # other SPEEDs [mm/s]

Each peak says where it was: ``approach`` (the INSERT's first segment, eq. 20-21) or the
time into the push (``push +0.48 s``): the push's start, the chamfer and the bore each
peak in their own way. The suite runs a few of the cases.
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

import cosmos

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_run_insert_speed import INSERT_LINE, PROGRAM, WINDOW_TICKS  # noqa: E402

SPEEDS_MMPS = (5.0, 10.0, 20.0, 30.0)
SEEDS = range(5)


def peak_mmps(speed_mmps: float, ideal: bool, seed: int, directory: Path) -> tuple[float, bool, str]:
    """The INSERT's peak speed along its axis [mm/s], whether the run succeeded, and where it peaked."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        log = directory / f"insert_{speed_mmps:g}_{seed}.mcap"
        run = cosmos.run(PROGRAM.format(speed=f" SPEED {speed_mmps:g} mm/s"), log=log, ideal=ideal, seed=seed)
    state = run.record.state
    inserting = state.line == INSERT_LINE
    t, z = state.t[inserting], state.x[inserting, 2]
    down = -(z[WINDOW_TICKS:] - z[:-WINDOW_TICKS]) / (t[WINDOW_TICKS:] - t[:-WINDOW_TICKS])
    peak = int(np.argmax(down))
    push_start = run.segments[-1].t if run.segments[-1].line == INSERT_LINE else np.inf
    end = t[peak + WINDOW_TICKS]  # the window's last sample
    where = "approach" if end < push_start else f"push +{end - push_start:.2f} s"
    return float(down[peak]) * 1e3, run.ok, where


def speeds_asked(arguments: list[str]) -> tuple[float, ...]:
    """The SPEEDs [mm/s] after ``--speeds`` (comma-separated), else :data:`SPEEDS_MMPS`."""
    if "--speeds" not in arguments:
        return SPEEDS_MMPS
    index = arguments.index("--speeds") + 1
    try:
        speeds = tuple(float(value) for value in arguments[index].split(","))
    except (IndexError, ValueError):
        raise SystemExit("--speeds takes SPEEDs in mm/s separated by commas, e.g. --speeds 3,8") from None
    if not all(np.isfinite(speed) and speed > 0.0 for speed in speeds):
        raise SystemExit(f"--speeds: each SPEED must be a positive number of mm/s; got {arguments[index]}")
    return speeds


def main() -> None:
    ideal = "--ideal" in sys.argv[1:]
    speeds = speeds_asked(sys.argv[1:])
    print(f"{'ideal' if ideal else 'realistic'} plant: peak speed along the insertion axis [mm/s], seeds 0-4")
    with tempfile.TemporaryDirectory() as directory:
        for speed in speeds:
            peaks = [peak_mmps(speed, ideal, seed, Path(directory)) for seed in SEEDS]
            within = sum(peak <= 1.1 * speed and ok for peak, ok, _ in peaks)
            listed = ", ".join(f"{peak:.2f} ({where}{'' if ok else ', failed'})" for peak, ok, where in peaks)
            worst = max(peak for peak, _, _ in peaks) / speed - 1.0
            print(f"SPEED {speed:g}: {listed}; {within} of 5 within 10 %, worst {np.round(worst * 100, 1)} %")


if __name__ == "__main__":
    main()
