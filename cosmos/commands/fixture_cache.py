"""The workcell's fixture frames for ``cosmos check``, without building the scene each time.

The frames are MuJoCo's: :func:`cosmos.workcell.fixture_frames` compiles the
scene and reads its sites, which costs a check importing MuJoCo and compiling
the workcell (0.3 s, more than the rest of a short check). So the first check
on a machine computes them that way and keeps them in the user cache
(:mod:`cosmos.user_cache`), in a file named by a hash of the model files and
MuJoCo's installation (:func:`cosmos.user_cache.package_stamp`); later checks read
that file. A changed scene gets another file; a cache that cannot be read or written
only means computing them again.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cosmos.user_cache import cached_array, package_stamp, user_cache_root, write_whole

MODEL_DIR = Path(__file__).resolve().parents[1] / "models" / "puma560"
"""The workcell's model files (``cosmos.workcell.MODEL_DIR``, which imports MuJoCo)."""


@dataclass(frozen=True)
class CachedFrame:
    """A fixture frame read back from the cache (the attributes of ``cosmos.workcell.FixtureFrame``).

    Attributes:
        name: The frame's name in programs.
        position: Origin, world [m], read-only. # (3,)
        rotation: Frame to world, read-only. # (3, 3)
    """

    name: str
    position: np.ndarray
    rotation: np.ndarray


def model_digest(model_dir: Path = MODEL_DIR) -> str:
    """A hash of every model file and of MuJoCo's installation: what the frames depend on."""
    digest = hashlib.sha256()
    digest.update(package_stamp("mujoco").encode())
    for path in sorted(model_dir.rglob("*")):
        if path.is_file():
            digest.update(str(path.relative_to(model_dir)).encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()[:32]


def cache_file() -> Path:
    """Where this scene's frames are kept."""
    return user_cache_root() / "fixtures" / f"{model_digest()}.json"


def _read(path: Path) -> dict[str, CachedFrame]:
    entries = json.loads(path.read_text(encoding="utf-8"))
    if not isinstance(entries, dict) or not entries:
        raise ValueError("not a cache of frames")
    return {
        name: CachedFrame(
            name, cached_array(entry["position"], (3,)), cached_array(entry["rotation"], (3, 3))
        )
        for name, entry in entries.items()
    }


def _write(path: Path, frames: dict[str, CachedFrame]) -> None:
    text = json.dumps(
        {
            name: {"position": f.position.tolist(), "rotation": f.rotation.tolist()}
            for name, f in frames.items()
        }
    )
    write_whole(path, text)


def fixture_frames() -> dict[str, CachedFrame]:
    """The workcell's fixture frames by name: from the cache, else from the scene (then cached)."""
    path = cache_file()
    try:
        return _read(path)
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        pass
    from cosmos.workcell import fixture_frames as from_scene

    frames = {name: CachedFrame(name, frame.position, frame.rotation) for name, frame in from_scene().items()}
    try:
        _write(path, frames)
    except OSError:
        pass  # a read-only cache: computed again next time
    return frames
