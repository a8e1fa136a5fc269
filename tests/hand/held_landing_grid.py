"""A held object set down (docs/language.md, "A held OBJECT lands"): speeds x arms x plants.

Run ``python tests/hand/held_landing_grid.py`` (about 2 minutes on two cores; ``--speeds 15``,
``--robots panda``, ``--seeds 0,ideal`` to choose). Each case picks ``block_a`` (0.5 kg, 40 x 30
x 50 mm) off the table with the gripper, lifts it 10 mm, sets it down with ``CONTACT DOWN
FORCE 5 N SPEED v`` and holds it a ``WAIT 1 s``:

* the landing's peak: the largest contact force, along the approach, that MuJoCo computes
  between the held block and anything but the pads, at every physics step in the first
  0.3 s after the block first touched (the table), and the largest push the wrist sensor
  logged (at 1 kHz) in the same window [N];
* the push logged at the touch (the CONTACT's switch from approach to hold) [N];
* the push's least and largest over the WAIT, and whether the program ran done;
* how far the block moved in the pads from the GRASP to the end of the WAIT (MuJoCo's block
  against the tool body, along the tool's axis and across it) [mm].

The tool's own landing bar (CONTACT, "The landing") is ``max(1.5 f, f + 5 N)``: 10 N for 5 N.
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "run"))
from run_support import StepProbe  # noqa: E402

FORCE_N = 5.0
WINDOW_S = 0.3
GRASP_Z_MM = {"puma560": 32.5, "panda": 36.0}
"""The tool point's height over the block's base at the GRASP (the pads 12.5 mm, the Panda's
9.25 mm, below the block's top: programs/pick_and_place.cos, panda_pick_and_place.cos)."""


def program(robot: str, speed_mmps: float, lift_mm: float = 10.0) -> str:
    """Pick block_a, lift it ``lift_mm``, set it down at ``speed_mmps`` with 5 N, hold 0.3 s."""
    head = "ROBOT panda\n" if robot == "panda" else ""
    return (
        f"{head}TOOL GRIPPER\nSPEED 0.2 m/s\n"
        "MOVE TO table + (-160 mm, 170 mm, 80 mm)\n"
        f"MOVE TO table + (-160 mm, 170 mm, {GRASP_Z_MM[robot]:g} mm) SPEED 50 mm/s\n"
        "GRASP block_a FORCE 40 N WIDTH 40 mm\n"
        f"MOVE BY (0, 0, {lift_mm:g} mm) SPEED 50 mm/s\n"
        f"CONTACT DOWN FORCE {FORCE_N:g} N SPEED {speed_mmps:g} mm/s TIMEOUT 5 s\n"
        "WAIT 1 s\n"
    )


class LandingProbe(StepProbe):
    """Per physics step: MuJoCo's contact force on ``block`` from all but the pads, world z [N],
    and the block's position in the tool body's frame [m]."""

    def __init__(self, block: str = "block_a") -> None:
        super().__init__()
        self.block = block
        self.t: list[float] = []
        self.push: list[float] = []
        self.in_tool: list[np.ndarray] = []

    def sample(self, model: mujoco.MjModel, data: mujoco.MjData, t: float) -> None:
        block = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, self.block)
        tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tool")
        hand = {b for b in range(model.nbody) if b == tool or model.body_parentid[b] == tool}
        up = 0.0
        for i in range(data.ncon):
            contact = data.contact[i]
            b1, b2 = int(model.geom_bodyid[contact.geom[0]]), int(model.geom_bodyid[contact.geom[1]])
            if block not in (b1, b2) or (b1 in hand or b2 in hand):
                continue
            mujoco.mj_contactForce(model, data, i, self._force)
            on_geom2 = contact.frame.reshape(3, 3).T.dot(self._force[:3])  # geom1 pushes geom2
            up += float(on_geom2[2] if b2 == block else -on_geom2[2])  # what holds the block up
        rotation = data.xmat[tool].reshape(3, 3)
        self.t.append(t)
        self.push.append(up)
        self.in_tool.append(rotation.T.dot(data.xpos[block] - data.xpos[tool]))


@dataclass(frozen=True)
class Figures:
    """One case's figures."""

    ok: bool
    touch_n: float
    peak_contact_n: float
    peak_log_n: float
    held_n: tuple[float, float]
    slip_mm: float


def measure(robot: str, speed_mmps: float, seed: int, ideal: bool, tmp: Path) -> Figures:
    """Run one case and read its figures."""
    path = tmp / "landing.cos"
    path.write_text(program(robot, speed_mmps), encoding="utf-8")
    log = tmp / "landing.mcap"
    out = io.StringIO()
    with LandingProbe() as probe, contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = run_program(path, log, Rates(state_hz=1000.0), seed, force=True, ideal=ideal)
    record = read_log(log)
    lines = program(robot, speed_mmps).splitlines()
    keys = ("GRASP", "CONTACT", "WAIT")
    line_of = {key: 1 + next(i for i, s in enumerate(lines) if s.startswith(key)) for key in keys}
    ct, cf = np.array(probe.t), np.array(probe.push)
    contact_start = [s.t for s in record.segments if s.line == line_of["CONTACT"]]
    grasped = [e.t for e in record.events if e.line == line_of["GRASP"] and e.kind == "done"]
    first = np.flatnonzero((cf > 0.0) & (ct >= (contact_start[0] if contact_start else math.inf)))
    if not first.size or not grasped:
        return Figures(False, math.nan, math.nan, math.nan, (math.nan, math.nan), math.nan)
    t0 = float(ct[first[0]])
    window = (ct >= t0) & (ct <= t0 + WINDOW_S)
    state = record.state
    push = -state.wrench[:, 2]
    logged = (state.t >= t0 - 1e-9) & (state.t <= t0 + WINDOW_S)
    holds = [s.t for s in record.segments if s.line == line_of["CONTACT"] and s.kind == "contact_hold"]
    at_touch = float(push[int(np.argmin(np.abs(state.t - holds[0])))]) if holds else math.nan
    waiting = state.line == line_of["WAIT"]
    in_tool = np.array(probe.in_tool)
    after_grasp = ct >= grasped[0] + 0.05
    moved = in_tool[after_grasp] - in_tool[after_grasp][0]
    return Figures(
        code == 0,
        at_touch,
        float(cf[window].max()),
        float(push[logged].max()),
        (float(push[waiting].min()), float(push[waiting].max())) if waiting.any() else (math.nan, math.nan),
        float(np.abs(moved).max()) * 1e3,
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", default="5,15,30", help="SPEEDs in mm/s, comma-separated")
    parser.add_argument("--robots", default="puma560,panda", help="puma560, panda")
    parser.add_argument("--seeds", default="0,1,2,3,ideal", help="realistic plant's seeds, 'ideal'")
    args = parser.parse_args()
    speeds = [float(s) for s in args.speeds.split(",")]
    print("robot    speed  seed  ok  touch  peak_mj peak_log  held (WAIT)  slip_mm")
    with tempfile.TemporaryDirectory() as tmp:
        for robot, speed, seed in itertools.product(args.robots.split(","), speeds, args.seeds.split(",")):
            ideal = seed == "ideal"
            f = measure(robot, speed, 0 if ideal else int(seed), ideal, Path(tmp))
            print(
                f"{robot:8s} {speed:5g} {seed:>5s} {int(f.ok):3d} {f.touch_n:6.2f} {f.peak_contact_n:8.2f} "
                f"{f.peak_log_n:8.2f} {f.held_n[0]:5.2f}-{f.held_n[1]:5.2f} {f.slip_mm:8.3f}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
