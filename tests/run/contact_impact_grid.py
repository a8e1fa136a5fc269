"""CONTACT's landing (issue 14, item 5): forces x speeds x surfaces x seeds, both plants.

Run ``python tests/run/contact_impact_grid.py`` (about 5 minutes on two cores; ``--forces 10``,
``--speeds 20,30``, ``--surfaces table``, ``--seeds 0,ideal``, ``--robot panda`` to choose). Each
case moves the tool above a surface, then ``CONTACT ... FORCE f SPEED v`` onto it and ``WAIT 0.3 s``:

* ``table``: ``CONTACT DOWN`` onto the table;
* ``slope``: ``CONTACT +Z IN slope`` onto the tilted plate, the tool square to it;
* ``turned``: ``CONTACT +Z IN turned`` onto the table, ``turned`` a task frame whose z points
  down and whose x and y are turned 45 deg about it;
* ``hole``: ``CONTACT DOWN`` onto the hole fixture's steel top face, 16 mm off the hole's axis
  (``programs/search_insert.cos``'s landing; not in the default surfaces): the approach lands
  slowly there (:mod:`cosmos.osc.landing`), and the figures add how long it took to touch [s].

The start is far enough above the surface for the approach to cruise at its SPEED for at
least 0.4 s. From the run's log, written at 1 kHz (every servo tick), and from MuJoCo's own
contact forces on the tool at every physics step (summed, projected on the approach
direction), it reports: the tool's speed along the approach as it first touched [mm/s]; the
peak of the logged push (the wrist sensor's, ``run.record.state.wrench``) and of MuJoCo's
contact force in the first 0.3 s after the touch [N]; the lowest logged push and MuJoCo contact force
after that peak within the 0.3 s (a bounce off the surface shows as a contact force of 0), and how long
MuJoCo's contact force was 0 in the window [ms]; and the contact_hold's settle time [s]. A case meets
the bar (docs/language.md, CONTACT) when both peaks are under ``max(1.5 f, f + 5 N)``.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import itertools
import math
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from cosmos.commands.run import run_program
from cosmos.runlog import read_log
from cosmos.runtime.rates import Rates

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run_support import StepProbe  # noqa: E402

SURFACES = ("table", "slope", "turned")
"""The default surfaces; ``hole`` is the fourth."""
TILT = math.radians(20.0)
DIRECTIONS = {
    "table": np.array([0.0, 0.0, -1.0]),
    "slope": -np.array([math.sin(TILT), 0.0, math.cos(TILT)]),  # the slope frame's z: into the face
    "turned": np.array([0.0, 0.0, -1.0]),
    "hole": np.array([0.0, 0.0, -1.0]),
}
WINDOW_S = 0.3
"""The impact is judged over this time after the touch [s]."""


def bar_n(force_n: float) -> float:
    """The documented bound on the landing's peak for a FORCE [N]."""
    return max(1.5 * force_n, force_n + 5.0)


def program(surface: str, force_n: float, speed_mmps: float) -> str:
    """The case's program: to the start, the CONTACT, a WAIT that covers the window."""
    gap_mm = max(6.0, 0.5 * speed_mmps)  # 0.4 s at the SPEED after its ramp
    clause = f"FORCE {force_n:g} N SPEED {speed_mmps:g} mm/s TIMEOUT 10 s"
    if surface == "table":
        return f"MOVE TO table + (0, 0, {gap_mm:g} mm)\nCONTACT DOWN {clause}\nWAIT 0.3 s\n"
    if surface == "hole":
        beside = f"FRAME beside = hole + (16 mm, 0, {gap_mm:g} mm)\nMOVE TO beside\n"
        return f"{beside}CONTACT DOWN {clause}\nWAIT 0.3 s\n"
    if surface == "slope":
        off = f"({gap_mm * math.sin(TILT):.4f} mm, 0, {gap_mm * math.cos(TILT):.4f} mm)"
        return f"MOVE TO slope + {off}\nCONTACT +Z IN slope {clause}\nWAIT 0.3 s\n"
    return (
        "FRAME turned = (600 mm, -150 mm, 200 mm) RPY (180 deg, 0, 45 deg)\n"
        f"MOVE TO (600 mm, -150 mm, {200 + gap_mm:g} mm)\nCONTACT +Z IN turned {clause}\nWAIT 0.3 s\n"
    )


class ContactProbe(StepProbe):
    """MuJoCo's contact force on the tool at every physics step, world [N]."""

    def __init__(self) -> None:
        super().__init__()
        self.t: list[float] = []
        self.f: list[np.ndarray] = []

    def sample(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> None:
        tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tool")
        total = np.zeros(3)
        for i in range(data.ncon):
            contact = data.contact[i]
            b1, b2 = model.geom_bodyid[contact.geom[0]], model.geom_bodyid[contact.geom[1]]
            if tool not in (b1, b2):
                continue
            mujoco.mj_contactForce(model, data, i, self._force)
            on_geom2 = contact.frame.reshape(3, 3).T.dot(self._force[:3])  # geom1 pushes geom2
            total += on_geom2 if b2 != tool else -on_geom2  # the force the tool applies
        self.t.append(t)
        self.f.append(total)


@dataclass(frozen=True)
class Figures:
    """One case's figures."""

    ok: bool
    touch_speed_mmps: float
    peak_log_n: float
    peak_contact_n: float
    lowest_n: float
    lowest_contact_n: float
    lost_s: float
    settle_s: float
    touch_s: float


def measure(
    surface: str, force_n: float, speed_mmps: float, seed: int, ideal: bool, tmp: Path, robot: str = ""
) -> Figures:
    """Run one case and read its figures (``robot``: a ROBOT statement's arm, or the PUMA)."""
    path = tmp / "impact.cos"
    prefix = f"ROBOT {robot}\n" if robot else ""
    path.write_text(prefix + program(surface, force_n, speed_mmps), encoding="utf-8")
    log = tmp / "impact.mcap"
    out = io.StringIO()
    with ContactProbe() as probe, contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = run_program(path, log, Rates(state_hz=1000.0), seed, force=True, ideal=ideal)
    record = read_log(log)
    n = DIRECTIONS[surface]
    line = (3 if surface in ("turned", "hole") else 2) + bool(robot)
    touch = [e.t for e in record.events if e.kind == "contact"]
    ct, cf = np.array(probe.t), np.array(probe.f).dot(n)
    first = np.flatnonzero(cf > 0.0)
    if not touch or not first.size:
        return Figures(False, *(math.nan,) * 8)
    t0 = float(ct[first[0]])  # MuJoCo's first contact
    state = record.state
    push = state.wrench[:, :3].dot(n)
    speed = state.v[:, :3].dot(n)
    window = (state.t >= t0 - 1e-9) & (state.t <= t0 + WINDOW_S)
    at_touch = int(np.argmin(np.abs(state.t - t0)))
    peak = int(np.flatnonzero(window)[np.argmax(push[window])])
    after = window & (state.t >= state.t[peak])
    holds = [s for s in record.segments if s.line == line and s.kind == "contact_hold"]
    later = [s.t for s in record.segments if holds and s.segment == holds[0].segment + 1]
    settle = later[0] - holds[0].t if holds and later else math.nan
    started = [e.t for e in record.events if e.kind == "start" and e.line == line]
    contact_window = (ct >= t0) & (ct <= t0 + WINDOW_S)
    contact_after = contact_window & (ct >= ct[contact_window][np.argmax(cf[contact_window])])
    return Figures(
        code == 0,
        float(speed[at_touch]) * 1e3,
        float(push[peak]),
        float(cf[contact_window].max()),
        float(push[after].min()),
        float(cf[contact_after].min()),
        float(np.count_nonzero(cf[contact_window] <= 0.0)) * float(np.median(np.diff(ct))),
        float(settle),
        touch[0] - started[0] if started else math.nan,
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--forces", default="3,5,10,30", help="FORCEs in N, comma-separated")
    parser.add_argument("--speeds", default="5,10,20,30,50", help="SPEEDs in mm/s, comma-separated")
    parser.add_argument("--surfaces", default=",".join(SURFACES), help="table, slope, turned")
    parser.add_argument("--seeds", default="0,1,2,3,4,ideal", help="realistic plant's seeds, 'ideal'")
    parser.add_argument("--robot", default="", help="the arm (ROBOT statement): panda; the PUMA if not given")
    args = parser.parse_args()
    forces = [float(f) for f in args.forces.split(",")]
    speeds = [float(s) for s in args.speeds.split(",")]
    surfaces = args.surfaces.split(",")
    seeds = args.seeds.split(",")
    met = total = 0
    print(
        "surface  force speed  seed  ok  v_touch  peak_log peak_mj  lowest low_mj lost_ms settle touch_s bar"
    )
    worst: dict[tuple[str, float, float], float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for surface, force, speed, seed in itertools.product(surfaces, forces, speeds, seeds):
            ideal = seed == "ideal"
            f = measure(surface, force, speed, 0 if ideal else int(seed), ideal, Path(tmp), args.robot)
            peak = max(f.peak_log_n, f.peak_contact_n)
            ok = f.ok and peak <= bar_n(force)
            key = (surface, force, speed)
            worst[key] = max(worst.get(key, 0.0), peak / force)
            met += ok
            total += 1
            figures = (
                f"{f.touch_speed_mmps:8.1f} {f.peak_log_n:8.2f} {f.peak_contact_n:8.2f} {f.lowest_n:7.2f} "
                f"{f.lowest_contact_n:6.2f} {f.lost_s * 1e3:6.0f} {f.settle_s:7.3f} {f.touch_s:6.3f}"
            )
            verdict = "ok" if ok else "OVER"
            case = f"{surface:7s} {force:5g} {speed:5g} {seed:>5s} {int(f.ok):3d}"
            print(f"{case} {figures}  {verdict}", flush=True)
    print(f"\n{met} of {total} cases under max(1.5 f, f + 5 N) and succeeded")
    print("worst peak / FORCE per case (over the seeds):")
    for (surface, force, speed), ratio in worst.items():
        print(f"  {surface:7s} {force:4g} N {speed:4g} mm/s: {ratio:5.2f}")
    return 0 if met == total else 1


if __name__ == "__main__":
    sys.exit(main())
