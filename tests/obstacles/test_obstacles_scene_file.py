"""The workcell's scene with its obstacle slots, kept as a file (cosmos.obstacles.scene_file)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import mujoco
import pytest

from cosmos.errors import CosmosError
from cosmos.obstacles import scene_file
from cosmos.obstacles.scene import obstacle_scene_xml
from cosmos.workcell import SCENE_XML


def test_the_scene_is_kept_in_the_cache_and_leaves_no_temporary_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every run left a ``cosmos-obstacles-*`` directory under the temporary directory (the process
    skips the teardown that removes it): the scene must be one file in the user cache, written once,
    that MuJoCo compiles to the slotted workcell, and nothing new under the temporary directory."""
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path / "cache"))
    temporary = tmp_path / "tmp"
    temporary.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temporary))
    obstacle_scene_xml.cache_clear()
    try:
        path = obstacle_scene_xml(8)
        assert path.parent == tmp_path / "cache" / "scenes" and list(temporary.iterdir()) == []
        written = path.stat().st_mtime_ns
        obstacle_scene_xml.cache_clear()
        assert obstacle_scene_xml(8) == path and path.stat().st_mtime_ns == written  # kept, not rewritten
        model = mujoco.MjModel.from_xml_path(str(path))
        plain = mujoco.MjModel.from_xml_path(str(SCENE_XML))
        assert model.ngeom == plain.ngeom + 8 and model.nbody == plain.nbody
    finally:
        obstacle_scene_xml.cache_clear()


def test_no_writable_place_is_one_clear_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """With the cache and every temporary directory read-only a run died with ``FileNotFoundError: No
    usable temporary directory found``: it must be one line naming the cache and COSMOS_CACHE_DIR."""
    blocker = tmp_path / "not_a_directory"
    blocker.write_text("")
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(blocker / "cache"))

    def no_temporary_directory(**_: object) -> object:
        raise FileNotFoundError(2, "No usable temporary directory found")

    monkeypatch.setattr(scene_file.tempfile, "TemporaryDirectory", no_temporary_directory)
    scene_file._scene_dir.cache_clear()
    try:
        with pytest.raises(CosmosError) as raised:
            scene_file.kept_scene_file("scene", "<mujoco/>")
    finally:
        scene_file._scene_dir.cache_clear()
    message = str(raised.value)
    assert "\n" not in message and str(blocker / "cache" / "scenes") in message
    assert "COSMOS_CACHE_DIR" in message
