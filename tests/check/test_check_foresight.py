"""``cosmos check`` prints what ``cosmos run`` foresees (joint limits, goals inside a fixture),
from a user cache that spares it MuJoCo."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from click.testing import CliRunner

from cosmos.cli import cli
from cosmos.robot_model import build_robot_model
from cosmos.robots import ROBOTS
from cosmos.runtime import foresight_cache
from cosmos.workcell import home_q

PROGRAM = """\
MOVE TO (600 mm, -150 mm, 350 mm) RPY (165 deg, -30 deg, 0)
MOVE TO table + (0, 0, -30 mm)
"""


@pytest.fixture()
def program(tmp_path: Path) -> Path:
    path = tmp_path / "slips.cos"
    path.write_text(PROGRAM)
    return path


def test_check_prints_the_runs_foreseen_warnings(program: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``cosmos check`` prints the joint limit that stops line 1 and the goal inside the table on
    line 2, in ``file:line:col`` form, word for word as ``cosmos run`` prints them before it starts.
    Catches the check command leaving out what only the run foresaw (it printed neither)."""
    from cosmos.commands.run import compile_file

    result = CliRunner().invoke(cli, ["check", str(program)])
    assert result.exit_code == 0, result.output
    compile_file(program)
    printed_by_run = capsys.readouterr().err
    assert result.stderr == printed_by_run
    lines = [line for line in result.stderr.splitlines() if ": warning: " in line]
    assert lines[0].startswith(f"{program}:1:1: warning: MOVE TO: joint 6 would reach its limit of 266 deg")
    assert lines[1] == (
        f"{program}:2:1: warning: MOVE TO: the goal is 30.0 mm inside the fixture 'table' "
        "(below its top at z = 200.0 mm); the run will stop at the touch"
    )


def test_check_json_carries_them(program: Path) -> None:
    """``cosmos check --json`` lists both warnings with their line and column. Catches the JSON
    plan written from the plan before the foresight was added."""
    result = CliRunner().invoke(cli, ["check", "--json", str(program)])
    assert result.exit_code == 0, result.output
    warnings = json.loads(result.stdout)["warnings"]
    assert [(w["line"], w["column"]) for w in warnings] == [(1, 1), (2, 1)]
    assert warnings[0]["message"].startswith("MOVE TO: joint 6 would reach its limit of 266 deg")
    assert warnings[1]["message"].startswith("MOVE TO: the goal is 30.0 mm inside the fixture 'table'")


@pytest.fixture()
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path))
    return tmp_path


@pytest.mark.parametrize("robot", ["puma560", "panda"])
def test_cached_kinematics_are_the_controllers(cache_dir: Path, robot: str) -> None:
    """The arm's kinematics read back from the cache file put the tool where the controller's model
    (built from the MJCF) puts it, at random configurations, with the same joint ranges and home.
    Catches a model serialised without its tool frame, or read back as another arm's."""
    foresight_cache.load_workcell(robot)  # computed, written
    assert foresight_cache.cache_file(ROBOTS[robot]).is_file()
    cell = foresight_cache.load_workcell(robot)  # read back
    cached = pin.Model()
    cached.loadFromString(cell.model_text)
    built = build_robot_model(ROBOTS[robot])
    np.testing.assert_array_equal(cell.home_q, home_q(ROBOTS[robot]))
    np.testing.assert_array_equal(cached.lowerPositionLimit, built.q_lower_rad)
    np.testing.assert_array_equal(cached.upperPositionLimit, built.q_upper_rad)
    data = cached.createData()
    rng = np.random.default_rng(5)
    for _ in range(20):
        q = rng.uniform(built.q_lower_rad, built.q_upper_rad)
        pin.framesForwardKinematics(cached, data, q)
        pin.framesForwardKinematics(built.model, built.data, q)
        np.testing.assert_allclose(
            data.oMf[cell.tool_frame].homogeneous, built.data.oMf[built.tool_frame].homogeneous, atol=1e-12
        )


def test_a_damaged_cache_file_is_computed_again(cache_dir: Path) -> None:
    """A truncated file, a file of another shape and one whose model text is damaged are all
    computed again. Catches a bad cache making check fail with a traceback."""
    path = foresight_cache.cache_file(ROBOTS["puma560"])
    path.parent.mkdir(parents=True)
    good = foresight_cache.from_scene(ROBOTS["puma560"])
    for damage in ('{"solids": [', "[]", '{"solids": [], "model": 3}'):
        path.write_text(damage)
        cell = foresight_cache.load_workcell("puma560")
        assert len(cell.solids) == len(good.solids)
    text = json.loads(path.read_text())
    text["model"] = "22 serialization::archive garbage"
    path.write_text(json.dumps(text))
    foresight_cache.kinematics.cache_clear()
    foresight_cache.workcell.cache_clear()
    try:
        model = foresight_cache.kinematics("puma560").model
        assert model.nq == 6
    finally:
        foresight_cache.kinematics.cache_clear()
        foresight_cache.workcell.cache_clear()


def test_the_file_is_named_by_the_code_that_derives_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A change to the code that builds the kinematics or reads the solids names another file.
    Catches a cache that keeps an old tool frame after the model-building code changed."""
    code = tmp_path / "robot_model.py"
    code.write_text("a = 1\n")
    monkeypatch.setattr(foresight_cache, "DERIVING_CODE", (code,))
    before = foresight_cache.digest(ROBOTS["puma560"])
    code.write_text("a = 2\n")
    assert foresight_cache.digest(ROBOTS["puma560"]) != before


def test_a_program_checked_again_does_not_import_pinocchio(cache_dir: Path, program: Path) -> None:
    """Checked a second time, a program's joint-limit foresight is read from the user cache: the
    same warnings, without importing Pinocchio (or MuJoCo). Catches the kept result not being used
    (60 ms of every check), or being another chain's (warnings at the wrong statements)."""
    code = (
        "import sys; from pathlib import Path; "
        "from cosmos.lang import compile_program; from cosmos.commands.fixture_cache import fixture_frames; "
        "from cosmos.runtime.foresight import with_foreseen_limits; "
        f"p = Path({str(program)!r}); "
        "plan = with_foreseen_limits(compile_program(p.read_text(), str(p), fixture_frames())); "
        "print([(w.span.line, w.message) for w in plan.warnings]); "
        "print('pinocchio' in sys.modules, 'mujoco' in sys.modules)"
    )
    first = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    again = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    warnings, loaded = again.stdout.splitlines()
    assert warnings == first.stdout.splitlines()[0]
    assert "(1, 'MOVE TO: joint 6 would reach its limit of 266 deg" in warnings
    assert loaded == "False False"


def test_a_block_ends_what_is_foreseen() -> None:
    """After an IF (whose branch may move the arm) the same tilt is not foreseen, as after a
    CONTACT. Catches the foresight following on from the pose before the block."""
    from cosmos.api import check

    tilt = "MOVE TO (0.55, 0.0, 0.4) RPY (165 deg, -30 deg, 0)\n"
    assert any("would reach its limit" in w.message for w in check(tilt).warnings)
    after_if = "MOVE TO (0.55, 0.0, 0.4)\nIF FORCE > 3 N\n  MOVE BY (0, 0, 50 mm)\nEND\n" + tilt
    assert not [w for w in check(after_if).warnings if "would reach its limit" in w.message]


def test_the_kept_chains_are_bounded(cache_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Beyond KEPT_CHAINS, the oldest kept chains are removed and the newest stay readable.
    Catches a cache that grows with every program ever checked."""
    monkeypatch.setattr(foresight_cache, "KEPT_CHAINS", 3)
    for number in range(5):
        foresight_cache.keep_foreseen("puma560", "peg", f"chain {number}".encode(), [(number, "m")])
    folder = next(path for path in cache_dir.glob("foresight/*") if path.is_dir())
    assert len(list(folder.glob("*.json"))) == 3
    assert foresight_cache.foreseen("puma560", "peg", b"chain 4") == [(4, "m")]


@pytest.mark.parametrize(("height_mm", "foreseen"), [(12.0, True), (13.0, False)])
def test_the_fingertips_past_the_tool_point_are_foreseen(height_mm: float, foreseen: bool) -> None:
    """A gripper sent 12 mm above the table puts its fingertips 0.5 mm into it: the check warns,
    and the run (MuJoCo's contacts) stops there; 13 mm: no warning, and the run arrives.

    Catches the checker testing the tool's axis back from the tool point only: the gripper's
    fingers reach 12.5 mm past it, and `MOVE TO table + (..., 12 mm)` before a GRASP passed the
    check, then stopped: "protective stop: finger_left hit fixture 'table'"."""
    import warnings

    import cosmos
    from cosmos.lang import compile_program
    from cosmos.runtime.foresight import with_foreseen_limits
    from cosmos.workcell import fixture_frames

    program = "TOOL GRIPPER\nMOVE TO table + (-160 mm, 250 mm, 60 mm)\n"
    program += f"MOVE TO table + (-160 mm, 250 mm, {height_mm} mm) SPEED 50 mm/s\n"
    compiled = with_foreseen_limits(compile_program(program, "tip.cos", fixture_frames()))
    said = [w.message for w in compiled.warnings if "tool's tip" in w.message]
    assert bool(said) is foreseen, said
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(program, log=None, ideal=True)
    assert run.ok is not foreseen, run.outcome
    if foreseen:
        assert run.outcome is not None and "finger" in run.outcome.reason and "table" in run.outcome.reason


def test_a_held_object_is_the_tool_past_its_point() -> None:
    """After GRASP the tool point is the held object's base: no fingertip warning for the
    shipped pick_and_place.cos's set-down 3 mm above the table; after RELEASE, the fingers again.
    Catches the gripper's fingertips tested below a held object's base."""
    from cosmos.lang import compile_program
    from cosmos.runtime.foresight import with_foreseen_limits
    from cosmos.workcell import fixture_frames

    source = (Path(__file__).parents[2] / "programs" / "pick_and_place.cos").read_text()
    source += "MOVE TO table + (120 mm, 80 mm, 5 mm)\n"
    compiled = with_foreseen_limits(compile_program(source, "pick.cos", fixture_frames()))
    tips = [w for w in compiled.warnings if "tool's tip" in w.message]
    assert [w.span.line for w in tips] == [len(source.splitlines())]


@pytest.mark.parametrize(
    ("robot", "goal_x_m", "beyond"), [("puma560", 1.2, True), ("puma560", 0.8, False), ("panda", 0.9, True)]
)
def test_a_goal_out_of_reach_is_foreseen_as_the_run_fails(robot: str, goal_x_m: float, beyond: bool) -> None:
    """The check names a goal out of the arm's reach with the run's own words and figure.

    Catches `MOVE TO (1.2, 0, 0.4)` (325 mm beyond the PUMA's 877 mm) checked as "joint 5 would
    reach its limit of -100 deg; the goal is within range in another configuration of the
    wrist": the rotation plan's stop, while the run fails "the pose is out of the arm's reach"."""
    import warnings

    import cosmos
    from cosmos.api import check

    program = f"ROBOT {robot}\nMOVE TO ({goal_x_m}, 0, 0.4)\n"
    said = [w.message for w in check(program).warnings if "reach" in w.message]
    if not beyond:
        assert not said, said
        return
    assert len(said) == 1 and said[0].startswith("MOVE TO: the pose is out of the arm's reach"), said
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(program, log=None, ideal=True)
    assert run.outcome is not None and not run.ok
    assert said[0].removeprefix("MOVE TO: ") in run.outcome.reason, (said, run.outcome.reason)


@pytest.mark.parametrize(("timeout_s", "foreseen"), [(2.0, True), (6.0, False)])
def test_a_contact_timeout_too_short_for_its_approach_is_foreseen(timeout_s: float, foreseen: bool) -> None:
    """``MOVE TO table + (0, 0, 100 mm)`` then ``CONTACT DOWN ... TIMEOUT 2 s`` passed the check and
    failed "found no contact within 2 s" (100 mm at the CONTACT's 20 mm/s is 5 s): the check must
    warn, naming the table 100 mm ahead, and the run confirm it; 6 s is enough, and no warning."""
    import warnings

    import cosmos
    from cosmos.api import check

    program = f"MOVE TO table + (0, 0, 100 mm)\nCONTACT DOWN FORCE 10 N TIMEOUT {timeout_s:g} s\n"
    said = [w.message for w in check(program).warnings if "ends this approach" in w.message]
    assert bool(said) is foreseen, said
    if foreseen:
        assert "'table' 100.0 mm ahead, at least 5.00 s at 20 mm/s" in said[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(program, log=None, ideal=True)
    assert run.ok is not foreseen, run.outcome
    if foreseen:
        assert run.outcome is not None and f"found no contact within {timeout_s:g} s" in run.outcome.reason


def test_a_contact_from_a_pose_the_text_does_not_fix_is_not_judged() -> None:
    """After a CONTACT the pose is not known (where it touched): no approach time is foreseen, as no
    goal is. Catches the check judging a CONTACT from a pose it made up."""
    from cosmos.api import check

    known = "MOVE TO table + (0, 0, 100 mm)\nMOVE BY (0, 0, 20 mm)\nCONTACT DOWN FORCE 10 N TIMEOUT 1 s\n"
    said = [w.message for w in check(known).warnings if "ends this approach" in w.message]
    assert said and "'table' 120.0 mm ahead" in said[0]
    after_contact = known.replace("MOVE BY", "CONTACT DOWN FORCE 5 N\nMOVE BY")
    assert not [w for w in check(after_contact).warnings if "ends this approach" in w.message]
