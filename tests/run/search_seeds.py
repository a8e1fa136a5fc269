"""INSERT ... SEARCH SPIRAL from lateral errors beyond the hole's mouth, seed by seed (issue 22, item 4).

The peg's end is flat, chamfered 1.5 mm, and the hole's mouth is chamfered 1 mm
(docs/workcell.md): a plain compliant INSERT goes in while the chamfers meet, up to
about 2.6 mm off the axis, and jams on the flat top beyond (tests/run/test_run_insert.py;
8 mm off, it jams). Each case here starts 16-18.4 mm off, in several directions:
without SEARCH the INSERT jams; with ``SEARCH SPIRAL RADIUS 20 mm PITCH 6 mm`` it
must reach its depth with the tip on the hole's axis.

Run every case with ten noise seeds (the README's Measured table)::

    python tests/run/search_seeds.py          # about 3 minutes on 2 cores

The suite (tests/run/test_run_search.py) runs two of them.
"""

from __future__ import annotations

import contextlib
import io
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run_support import HOLE_MOUTH_M, ProgramRun, read_run, samples_of, write_program  # noqa: E402

SEARCH = "SEARCH SPIRAL RADIUS 20 mm PITCH 6 mm"
CASES_MM = ((16.0, 0.0), (0.0, -16.0), (-13.0, 13.0), (12.0, 12.0))
"""Lateral errors of the start [mm], world x and y: 16, 16, 18.4 and 17 mm off the axis."""
DEPTH_M = 0.025
ON_AXIS_M = 1.5e-3
"""The tip within this of the hole's axis once inserted [m]: the radial clearance is 0.12 mm
(0.32 mm to the polygon's corners); 25 mm below the mouth the tip can only be in the hole
(radius 10.03 mm)."""


def program(dx_mm: float, dy_mm: float, search: str) -> str:
    """Touch the top beside the hole at the error, then INSERT (with ``search``, or not)."""
    return (
        f"MOVE TO hole + ({dx_mm:g} mm, {dy_mm:g} mm, 15 mm)\n"
        "CONTACT DOWN FORCE 8 N TIMEOUT 5 s\n"
        f"INSERT DOWN DEPTH 25 mm FORCE 15 N {search} TIMEOUT 30 s\n"
    )


def run_seeded(directory: Path, name: str, source: str, seed: int, ideal: bool = False) -> ProgramRun:
    """Run ``source`` in this process with the sensor noise (and realistic plant) of ``seed``."""
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates

    path = write_program(directory, name, source)
    log = directory / f"{name}.mcap"
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = run_program(path, log, Rates(), seed, force=True, ideal=ideal)
    return read_run(path, log, code, out.getvalue(), err.getvalue())


@dataclass(frozen=True)
class Inserted:
    """What the INSERT did, from the log."""

    outcome: str
    reason: str
    found: str
    depth_m: float
    """Deepest tip position below the mouth [m]."""
    off_axis_m: float
    """The tip's distance from the hole's axis at the deepest point [m]."""


def inserted(run: ProgramRun) -> Inserted:
    """The INSERT's outcome and where the tip went (world, from the state samples)."""
    line = run.line_of("INSERT")
    ends = [e for e in run.events(line=line) if e.kind in ("done", "failed", "stopped")]
    found = [e.reason for e in run.events("found", line)]
    mask = samples_of(run, [s.segment for s in run.segments("insert")])
    x = run.log.state.x[mask]
    deepest = int(np.argmin(x[:, 2]))
    return Inserted(
        outcome=ends[-1].kind if ends else "missing",
        reason=ends[-1].reason if ends else "",
        found=found[0] if found else "",
        depth_m=float(HOLE_MOUTH_M[2] - x[deepest, 2]),
        off_axis_m=float(np.hypot(*(x[deepest, :2] - HOLE_MOUTH_M[:2]))),
    )


def succeeded(result: Inserted) -> bool:
    """Done, with the tip 25 mm into the hole on its axis."""
    return result.outcome == "done" and result.depth_m > DEPTH_M - 1e-3 and result.off_axis_m < ON_AXIS_M


def main() -> None:
    """Every case without SEARCH once, and with SEARCH for seeds 0-9; a table of the results."""
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        for dx, dy in CASES_MM:
            plain = inserted(run_seeded(directory, "plain", program(dx, dy, ""), 0))
            print(f"({dx:g}, {dy:g}) mm without SEARCH: {plain.outcome}: {plain.reason}")
            wins = 0
            for seed in range(10):
                result = inserted(run_seeded(directory, "search", program(dx, dy, SEARCH), seed))
                wins += succeeded(result)
                print(
                    f"  seed {seed}: {result.outcome}, depth {result.depth_m * 1e3:.1f} mm, "
                    f"{result.off_axis_m * 1e3:.2f} mm off the axis; {result.found or result.reason}"
                )
            print(f"({dx:g}, {dy:g}) mm with {SEARCH}: {wins} of 10 seeds", flush=True)


if __name__ == "__main__":
    main()
