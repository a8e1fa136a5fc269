"""What an arm's model files give a run, computed once per model and kept in the user cache.

A run reads from the arm's workcell scene the home configuration and where the tool point
is there, the fixture frames and the tool's datasheet (:mod:`cosmos.workcell`), the arm's
capsules (:mod:`cosmos.obstacles.capsules`), the fixtures' contact ramps against the tool
(:mod:`cosmos.runtime.landing_zone`) and the drives' torque limits from the bare arm
(:mod:`cosmos.robot_model`). Computing them parses and compiles the scene and the arm with
MuJoCo (the scene once more for the gripper), and the capsules' containment tests take as
long again: about 45 million instructions, 7-15 ms of a warm ``cosmos run``, to find the
same numbers as the run before. So each value is kept (pickled, arrays as writable as they
were: :class:`cosmos.user_cache.ArrayPickler`) in one file per model,
``<user cache>/model-facts/<key>.pickle``, whose key names everything the values are made from:

* the content of every file in the arm's model directory (its scene and arm files);
* the content of the cosmos modules that compute them (:data:`COMPUTED_BY`);
* the libraries that compute them (MuJoCo, Pinocchio, numpy:
  :func:`cosmos.user_cache.package_stamp`) and Python's version.

A value not in the file is computed and the file written anew (whole, or not at all: a cache
that cannot be written only means computing every time); a file that cannot be read or
unpickled counts as empty. Each value is computed by the function that did so before this
cache existed, and read back by what kept it (``tests/test_model_facts.py`` compares the two).
"""

from __future__ import annotations

import functools
import hashlib
import io
import pickle
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from cosmos.user_cache import ArrayPickler, package_stamp, user_cache_root, write_whole

T = TypeVar("T")

FORMAT = b"cosmos-model-facts-1"
"""This file format's name and version (changed when the layout below changes)."""
PACKAGE_DIR = Path(__file__).resolve().parent
COMPUTED_BY = (
    "model_facts.py",
    "user_cache.py",
    "workcell.py",
    "robots.py",
    "robot_model.py",
    "obstacles/capsules.py",
    "hand/gripper_scene.py",
    "hand/tool.py",
    "runtime/landing_zone.py",
)
"""The cosmos modules (relative to the package) whose code computes the kept values."""
LIBRARIES = ("mujoco", "pinocchio", "numpy")
"""The installed packages that compute them."""


def facts_key(model_dir: Path) -> str:
    """The key of ``model_dir``'s facts: its files' and the computing code's content, the libraries, Python.

    Raises:
        OSError: If a file of the model directory cannot be read.
    """
    digest = hashlib.sha256(FORMAT)
    digest.update(sys.version.encode())
    for library in LIBRARIES:
        digest.update(package_stamp(library).encode() + b"\n")
    for name in COMPUTED_BY:
        digest.update(name.encode() + b"\0" + (PACKAGE_DIR / name).read_bytes())
    for path in sorted(model_dir.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(b"\0" + str(path.relative_to(model_dir)).encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()[:32]


@dataclass
class _Kept:
    """One model's facts file and the values read from it (or computed since)."""

    path: Path | None
    values: dict[str, Any] = field(default_factory=dict)

    def write(self) -> None:
        """Write every value to the file (whole or not at all; not at all if it cannot be)."""
        if self.path is None:
            return
        stream = io.BytesIO()
        try:
            ArrayPickler(stream, protocol=pickle.HIGHEST_PROTOCOL).dump(self.values)
            write_whole(self.path, stream.getvalue())
        except (OSError, pickle.PicklingError, TypeError, AttributeError):
            return


@functools.cache
def _kept(root: Path, model_dir: Path) -> _Kept:
    """The facts of ``model_dir`` kept under ``root`` (read once per process and cache directory)."""
    try:
        path = root / "model-facts" / f"{facts_key(model_dir)}.pickle"
    except OSError:  # a model file that cannot be read: computing will say why
        return _Kept(None)
    try:
        values = pickle.loads(path.read_bytes())
    except Exception:  # missing, or damaged (unpickling can raise anything): computed again
        return _Kept(path)
    return _Kept(path, values if isinstance(values, dict) else {})


def kept(model_dir: Path, name: str, compute: Callable[[], T]) -> T:
    """The value ``name`` of the model in ``model_dir``: kept by an earlier run, else ``compute()`` (kept).

    Args:
        model_dir: The arm's model directory (every file in it is part of the key).
        name: The value's name within the model's facts, its arguments included
            (``tool_spec:gripper``).
        compute: Computes the value from the model files; called only if it is not kept.
    """
    facts = _kept(user_cache_root(), model_dir.resolve())
    if name in facts.values:
        return facts.values[name]
    value = compute()
    facts.values[name] = value
    facts.write()
    return value
