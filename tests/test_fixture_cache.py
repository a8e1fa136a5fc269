"""``cosmos check`` reads the fixture frames from the user cache instead of compiling the scene."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cosmos.commands import fixture_cache
from cosmos.runtime import foresight_cache
from cosmos.workcell import fixture_frames


@pytest.fixture()
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path))
    return tmp_path


def test_cached_frames_are_the_scenes(cache_dir: Path) -> None:
    """Catches a cache that stores or reads back frames other than MuJoCo's sites (first from the
    scene, then from the file)."""
    scene = fixture_frames()
    first = fixture_cache.fixture_frames()
    assert fixture_cache.cache_file().is_file()
    again = fixture_cache.fixture_frames()
    for frames in (first, again):
        assert set(frames) == set(scene)
        for name, frame in scene.items():
            np.testing.assert_array_equal(frames[name].position, frame.position)
            np.testing.assert_array_equal(frames[name].rotation, frame.rotation)
            assert not frames[name].position.flags.writeable


def test_a_damaged_cache_file_is_computed_again(cache_dir: Path) -> None:
    """Catches a truncated or foreign cache file making check fail or read wrong frames."""
    path = fixture_cache.cache_file()
    path.parent.mkdir(parents=True)
    for damage in ('{"hole": {"position": [1, 2', '{"hole": {"position": [1, 2, "x"]}}', "[]"):
        path.write_text(damage)
        frames = fixture_cache.fixture_frames()
        np.testing.assert_array_equal(frames["hole"].position, fixture_frames()["hole"].position)


def test_a_changed_scene_gets_another_file(tmp_path: Path) -> None:
    """Catches a cache keyed by something that does not change with the model (a moved hole would
    keep its old frame)."""
    model = tmp_path / "model"
    model.mkdir()
    (model / "scene.xml").write_text("<mujoco/>")
    before = fixture_cache.model_digest(model)
    (model / "scene.xml").write_text("<mujoco> </mujoco>")
    assert fixture_cache.model_digest(model) != before


def test_check_does_not_load_the_simulator(cache_dir: Path, tmp_path: Path) -> None:
    """Catches `cosmos check` importing MuJoCo again (0.3 s of its start-up) once the frames are cached,
    and the foresight (joint limits, goals inside fixtures) loading it for the arm's kinematics."""
    fixture_cache.fixture_frames()
    foresight_cache.load_workcell("puma560")
    program = tmp_path / "p.cos"
    program.write_text("MOVE TO hole + (0, 0, 50 mm)\n")
    code = (
        "import sys, io; from pathlib import Path; from cosmos.commands.check import check_program; "
        f"assert check_program(Path({str(program)!r}), out=io.StringIO()) == 0; "
        "print('mujoco' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


def test_a_reinstalled_package_gets_another_stamp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches cache files named without the installed MuJoCo or Pinocchio (an upgrade rewrites the
    package's files; frames or kinematics from the old one would be read back)."""
    import os

    from cosmos.user_cache import package_stamp

    package = tmp_path / "stamped_pkg"
    package.mkdir()
    (package / "__init__.py").write_text("VERSION = 1\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    before = package_stamp("stamped_pkg")
    (package / "__init__.py").write_text("VERSION = 22\n")
    os.utime(package / "__init__.py", ns=(1, 1))
    assert package_stamp("stamped_pkg") != before
    assert package_stamp("no_such_package_here") == "none"
