"""What a run reads from the model files comes from the user cache (cosmos.model_facts) as they give it."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from cosmos import model_facts, workcell
from cosmos.hand.tool import Tool
from cosmos.obstacles import capsules
from cosmos.robot_model import _drive_torque_limits, drive_torque_limits
from cosmos.robots import PUMA560, ROBOTS, Robot
from cosmos.runtime import landing_zone


@pytest.fixture()
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def reread() -> None:
    """Forget what this process read from the facts files (and the scenes it compiled, by path):
    the next value comes from the file, or from the model files as they are now."""
    model_facts._kept.cache_clear()
    workcell._compiled_at_home.cache_clear()


def assert_same(kept: Any, computed: Any, where: str) -> None:
    """Equal bit for bit, of the same types, arrays as writable as the computed ones."""
    assert type(kept) is type(computed), where
    if isinstance(computed, np.ndarray):
        assert kept.dtype == computed.dtype and kept.shape == computed.shape, where
        assert kept.tobytes() == computed.tobytes(), where
        assert kept.flags.writeable == computed.flags.writeable, where
    elif dataclasses.is_dataclass(computed):
        for field in dataclasses.fields(computed):
            assert_same(getattr(kept, field.name), getattr(computed, field.name), f"{where}.{field.name}")
    elif isinstance(computed, tuple):
        assert len(kept) == len(computed), where
        for i, (a, b) in enumerate(zip(kept, computed, strict=True)):
            assert_same(a, b, f"{where}[{i}]")
    else:
        assert kept == computed, where


def kept_values(robot: Robot) -> dict[str, Any]:
    """Every fact of ``robot`` a run reads, through the cache."""
    values: dict[str, Any] = {
        "home_q": workcell.home_q.__wrapped__(robot),
        "fixtures": workcell._read_fixture_frames.__wrapped__(robot.scene_xml),
        "capsules": capsules._scene_capsules.__wrapped__(robot.scene_xml),
        "drive_limits": _drive_torque_limits(robot),
        "contact_ramps": landing_zone.contact_ramps.__wrapped__(robot.name),
    }
    for tool in Tool:
        values[f"tool_spec {tool.value}"] = workcell.tool_spec.__wrapped__(robot, tool)
    return values


def computed_values(robot: Robot) -> dict[str, Any]:
    """The same facts computed from the model files (the code before the cache)."""
    values: dict[str, Any] = {
        "home_q": workcell.home_q_from_scene(robot),
        "fixtures": workcell.fixture_frames_from_scene(robot.scene_xml),
        "capsules": capsules.scene_capsules(robot.scene_xml),
        "drive_limits": drive_torque_limits(robot),
        "contact_ramps": landing_zone.contact_ramps_from_scene(robot.name),
    }
    for tool in Tool:
        values[f"tool_spec {tool.value}"] = workcell.tool_spec_from_scene(robot, tool)
    return values


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_kept_facts_are_the_models(cache_dir: Path, name: str) -> None:
    """Catches a cache that keeps or reads back other numbers than the model files give (a value
    stored under another's name, an array read back rounded, reordered or writable where the
    computed one is read-only), computed in a first run and read from the file in the next."""
    robot = ROBOTS[name]
    computed = computed_values(robot)
    reread()
    first = kept_values(robot)
    assert list((cache_dir / "model-facts").iterdir()), "nothing was kept"
    reread()
    again = kept_values(robot)
    for values in (first, again):
        for key, value in computed.items():
            assert_same(values[key], value, key)


def test_the_module_constants_are_the_scenes() -> None:
    """Catches the PUMA's constants read at import from a cache that no longer matches its scene."""
    assert_same(workcell.HOME_Q, workcell.home_q_from_scene(PUMA560), "HOME_Q")
    position, rotation = workcell.home_tool_from_scene(PUMA560.scene_xml)
    assert_same(workcell.HOME_TOOL_POSITION, position, "HOME_TOOL_POSITION")
    assert_same(workcell.HOME_TOOL_ROTATION, rotation, "HOME_TOOL_ROTATION")
    assert_same(workcell.TOOL, workcell.tool_spec_from_scene(PUMA560), "TOOL")


def copied_puma(tmp_path: Path) -> Robot:
    """The PUMA with its model files copied to ``tmp_path``."""
    model_dir = tmp_path / "puma560"
    shutil.copytree(PUMA560.model_dir, model_dir)
    return dataclasses.replace(
        PUMA560,
        model_dir=model_dir,
        arm_xml=model_dir / PUMA560.arm_xml.name,
        scene_xml=model_dir / PUMA560.scene_xml.name,
    )


def test_a_changed_model_is_computed_again(cache_dir: Path, tmp_path: Path) -> None:
    """Catches a stale cache after the model changes: the home keyframe moved in the scene file
    must give the new home, not the one kept from the file before."""
    robot = copied_puma(tmp_path)
    before = workcell.home_q.__wrapped__(robot)
    np.testing.assert_array_equal(before, workcell.HOME_Q)
    scene = robot.scene_xml.read_text()
    old = 'qpos="0 0.7853981633974483'
    assert old in scene
    robot.scene_xml.write_text(scene.replace(old, 'qpos="0.25 0.7853981633974483'))
    reread()
    after = workcell.home_q.__wrapped__(robot)
    assert after[0] == 0.25
    assert_same(after, workcell.home_q_from_scene(robot), "home_q")
    assert len(list((cache_dir / "model-facts").iterdir())) == 2


def test_changed_code_gets_another_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a key that leaves out the code computing the facts (a changed tool_spec would read
    the old datasheet back)."""
    package = tmp_path / "cosmos"
    for name in model_facts.COMPUTED_BY:
        (package / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(model_facts.PACKAGE_DIR / name, package / name)
    monkeypatch.setattr(model_facts, "PACKAGE_DIR", package)
    before = model_facts.facts_key(PUMA560.model_dir)
    (package / "workcell.py").write_text((package / "workcell.py").read_text() + "\n# changed\n")
    assert model_facts.facts_key(PUMA560.model_dir) != before


def test_a_damaged_file_is_computed_again(cache_dir: Path) -> None:
    """Catches a truncated or foreign facts file failing the run or giving other values."""
    path = cache_dir / "model-facts" / f"{model_facts.facts_key(PUMA560.model_dir)}.pickle"
    path.parent.mkdir(parents=True)
    computed = workcell.home_q_from_scene(PUMA560)
    for damage in (b"", b"\x80\x05not a pickle", b"\x80\x04K\x01."):  # the last: an int, not a dict
        path.write_bytes(damage)
        reread()
        assert_same(workcell.home_q.__wrapped__(PUMA560), computed, "home_q")


def test_a_read_only_cache_still_gives_the_facts(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a cache directory that cannot be written failing the run instead of computing."""
    blocked = tmp_path / "file"
    blocked.write_text("not a directory")
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(blocked))
    reread()
    assert_same(workcell.home_q.__wrapped__(PUMA560), workcell.home_q_from_scene(PUMA560), "home_q")
