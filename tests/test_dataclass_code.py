"""The methods ``@dataclass`` writes, compiled once and kept: the same code Python compiles, or none kept."""

from __future__ import annotations

import dataclasses
import marshal
from pathlib import Path

import pytest

from cosmos.commands import dataclass_code
from cosmos.commands.dataclass_code import CachedExec, read_codes


def _define() -> type:
    @dataclasses.dataclass(frozen=True)
    class Pose:
        x: float
        y: float = 2.0

    return Pose


def test_a_class_defined_again_finds_its_methods_compiled_and_they_are_pythons(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches a cached method that is not what Python itself compiles from the same text (compiled
    under this module's ``from __future__ import annotations``, say, whose annotations are strings),
    and a cache that compiles a text it already holds."""
    cached = CachedExec({})
    monkeypatch.setattr(dataclasses, "exec", cached, raising=False)
    first = _define()
    compiled = cached.compiled
    assert compiled >= 4  # __init__, __repr__, __eq__, __hash__, __setattr__, __delattr__
    again = _define()
    assert cached.compiled == compiled
    pose = again(1.0)
    assert (pose, repr(pose), pose == again(1.0, 2.0)) == (
        again(1.0, 2.0),
        "_define.<locals>.Pose(x=1.0, y=2.0)",
        True,
    )
    with pytest.raises(dataclasses.FrozenInstanceError):
        pose.x = 3.0  # type: ignore[misc]
    assert first.__init__.__annotations__ == {"x": "float", "y": "float", "return": None}
    path = tmp_path / "codes.marshal"
    cached.keep(path)
    kept = read_codes(path)
    assert set(kept) == cached.used and len(kept) == compiled
    for text, code in kept.items():
        assert type(code) is bytes  # read back when its class is defined, not at start-up
        assert marshal.loads(code) == compile(text, "<string>", "exec", dont_inherit=True)
    reread = CachedExec(kept)
    monkeypatch.setattr(dataclasses, "exec", reread, raising=False)
    _define()
    assert reread.compiled == 0 and reread.used == cached.used


def test_an_unreadable_cache_is_ignored_and_an_unwritable_one_not_kept(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches a start-up that fails on a damaged cache file (a run cut while another wrote it, a
    file of another Python, an entry that is not code) or on a cache directory it cannot write (a
    read-only home)."""
    broken = tmp_path / "codes.marshal"
    broken.write_bytes(b"\x00not marshal data")
    assert read_codes(broken) == {}
    broken.write_bytes(marshal.dumps({"text": 3, 4: "x", "also": compile("1", "<string>", "exec")}))
    assert read_codes(broken) == {}
    damaged = CachedExec({"x = 1": b"\xe3not code", "y = 2": marshal.dumps(3)})
    namespace: dict[str, int] = {}
    damaged("x = 1", namespace)
    damaged("y = 2", namespace)
    assert (namespace["x"], namespace["y"], damaged.compiled) == (1, 2, 2)
    cached = CachedExec(read_codes(broken))
    monkeypatch.setattr(dataclasses, "exec", cached, raising=False)
    _define()
    not_a_directory = tmp_path / "file"
    not_a_directory.write_text("")
    cached.keep(not_a_directory / "codes.marshal")  # no exception
    assert not (not_a_directory / "codes.marshal").exists()


def test_install_gives_dataclasses_the_cached_exec_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches a second install stacking a cache on a cache, and the cache file not read from the
    user cache (``COSMOS_CACHE_DIR``)."""
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path))
    monkeypatch.delattr(dataclasses, "exec", raising=False)
    seed = CachedExec({})
    monkeypatch.setattr(dataclasses, "exec", seed, raising=False)
    _define()
    seed.keep(tmp_path / dataclass_code.CACHE_NAME)
    monkeypatch.delattr(dataclasses, "exec")
    installed = dataclass_code.install()
    try:
        assert installed is not None and dataclass_code.install() is None
        _define()
        assert installed.compiled == 0 and installed.used == seed.used
    finally:
        monkeypatch.delattr(dataclasses, "exec")
