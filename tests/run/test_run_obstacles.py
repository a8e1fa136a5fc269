"""OBSTACLE through ``cosmos run``: bodies in the workcell, the field, local minima, collision events.

The avoidance itself (five scenes, avoidance on and off) is tested in
tests/obstacles against the simulator; here a program written in the language
is judged by its log.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from run_support import BOTH_PLANTS, run_in_process, write_program

from cosmos.runlog.reader import read_log

# Home puts the tool at (0.596, -0.150, 0.457). A ball sits beside the straight
# line to (0.36, -0.15, 0.457): closer than its 100 mm influence, so the field acts.
AVOID = """\
SPEED 0.2 m/s
OBSTACLE ball SPHERE AT (480 mm, -90 mm, 460 mm) RADIUS 30 mm
MOVE TO (360 mm, -150 mm, 457 mm)
OBSTACLE REMOVE ball
MOVE BY (0, 0, 40 mm)
"""

# A wall straight across the path, wider than the arm can get round: a local minimum.
TRAPPED = """\
SPEED 0.2 m/s
OBSTACLE wall BOX AT (450 mm, -150 mm, 420 mm) SIZE (20 mm, 600 mm, 400 mm)
MOVE TO (300 mm, -150 mm, 457 mm) TIMEOUT 20 s
"""


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_the_arm_goes_round_a_ball_and_the_log_shows_it(tmp_path: Path, ideal: bool) -> None:
    """The MOVE TO round the ball arrives (done: within 1 mm and 1 deg) without a collision.

    Its goal has joint 3 7 deg from its limit of -225 deg, inside the task's joint-limit
    projection (17 deg) and the joint-limit field (8.6 deg): catches those zones reaching the
    goal itself, where the task gave up the last of its error and the field pushed back (it
    stopped 0.3-2.8 mm and up to 3.4 deg short on the realistic plant, depending on the seed,
    and failed after 2 s without progress)."""
    run = run_in_process(write_program(tmp_path, "avoid", AVOID), tmp_path / "avoid.mcap", ideal)
    assert run.returncode == 0, run.describe()
    record = read_log(tmp_path / "avoid.mcap")
    assert not [e for e in record.events if e.kind == "collision"]
    moves = [s for s in record.segments if s.line == 3]
    assert moves
    # The tool reached the goal within 5 mm, and the ball is drawn on /scene.
    end = record.state.x[record.state.line == 3][-1]
    assert np.linalg.norm(end - np.array((0.36, -0.15, 0.457))) < 0.005
    assert record.message_counts.get("/scene", 0) >= 3  # fixtures, the ball, its removal


def test_a_local_minimum_fails_with_the_obstacle_named_not_a_timeout(tmp_path: Path) -> None:
    run = run_in_process(write_program(tmp_path, "trapped", TRAPPED), tmp_path / "trapped.mcap")
    assert run.returncode == 1
    assert "stuck in a local minimum of the potential field near obstacle 'wall'" in run.stderr
    assert "trapped.cos:3:1:" in run.stderr
    failed = [e for e in read_log(tmp_path / "trapped.mcap").events if e.kind == "failed"]
    assert failed and failed[0].t < 20.0


def test_an_obstacle_placed_through_the_arm_fails_at_its_line(tmp_path: Path) -> None:
    # language.md's own wall example stands where the tool is at home (x = 0.596 m).
    program = "OBSTACLE wall BOX AT (0.6, 0, 0.3) SIZE (0.02, 0.6, 0.6)\nMOVE BY (0, 0, 50 mm)\n"
    run = run_in_process(write_program(tmp_path, "through", program), tmp_path / "through.mcap")
    assert run.returncode == 1
    assert "through.cos:1:1: OBSTACLE wall would be placed through the arm (tool inside it)" in run.stderr
    record = read_log(tmp_path / "through.mcap")
    assert [e.kind for e in record.events] == ["start", "failed"]


def _warned_and_refused(tmp_path: Path, name: str, source: str) -> tuple[str, str]:
    """The check's warning of an obstacle through the arm at home, and the run's refusal ("" if none)."""
    run = run_in_process(write_program(tmp_path, name, source), tmp_path / f"{name}.mcap")
    lines = run.stderr.splitlines()
    warned = next((line for line in lines if "through the arm at its home pose" in line), "")
    refused = next((line for line in lines if "would be placed through the arm (" in line), "")
    return warned, refused


def test_the_check_foresees_an_obstacle_through_the_arm_at_home_as_the_run_finds_it(tmp_path: Path) -> None:
    """Catches an OBSTACLE through the arm at home passing ``cosmos check`` (the Panda's lamp
    through link 5; the docs' lid PLANE lowered to 0.75 m through the PUMA's upper arm), found
    only when the run failed at t = 0. Judged against MuJoCo's own contacts where the run adds
    the obstacle: 24 spheres drawn grazing, touching or through the PUMA's
    links at home, each warned only if the run refuses
    it, naming no part the run does not (the check's capsules lie inside the arm's geoms)."""
    warned, refused = _warned_and_refused(
        tmp_path, "lamp", "ROBOT panda\nOBSTACLE lamp SPHERE AT (0.45, -0.05, 0.65) RADIUS 50 mm\nWAIT 1 ms\n"
    )
    assert "lamp.cos:2:1: warning: OBSTACLE lamp would be placed through the arm at its home pose" in warned
    assert "(link5 inside it)" in warned and "(link5 inside it)" in refused
    warned, refused = _warned_and_refused(
        tmp_path, "lid", "OBSTACLE lid PLANE AT (0, 0, 0.75) NORMAL (0, 0, -1)\n"
    )
    assert warned and refused
    from cosmos.runtime.foresight_cache import workcell

    arm = workcell("puma560", "peg").arm_at_home
    rng = np.random.default_rng(7)
    counts = {"warned": 0, "refused": 0}
    for draw in range(24):  # each a sphere grazing, touching or through a capsule's surface
        capsule = arm[rng.integers(len(arm))]
        on_axis = capsule.a + rng.uniform() * (capsule.b - capsule.a)
        away = rng.normal(size=3)
        radius = rng.uniform(0.02, 0.08)
        x, y, z = on_axis + away / np.linalg.norm(away) * (
            capsule.radius_m + radius + rng.uniform(-0.02, 0.02)
        )
        at = f"({x:.4f}, {y:.4f}, {z:.4f})"
        source = f"OBSTACLE s{draw} SPHERE AT {at} RADIUS {radius * 1000:.1f} mm\nWAIT 1 ms\n"
        warned, refused = _warned_and_refused(tmp_path, f"s{draw}", source)
        counts["warned"] += bool(warned)
        counts["refused"] += bool(refused)
        if warned:
            assert refused, (source, warned)
            parts = warned.split("home pose (")[1].split(")")[0].split(", ")
            assert all(part in refused for part in parts), (source, warned, refused)
    assert counts["warned"] >= 10 and counts["refused"] >= counts["warned"], counts
