"""A program file's compiled plan, kept in the user cache for the next ``cosmos run`` of it.

Compiling a program takes a warm ``cosmos run`` importing Lark and the language's
modules, loading the grammar, parsing, checking and compiling (about 50 ms of
``peg_in_hole.cos``'s 0.8 s), to make the same plan as the last run of the same
file. The plan is kept (pickled) in ``<user cache>/plans/``, one file per program
path and arm, under a key that names everything the plan is made from:

* the program's text, its path as given (the plan's spans and messages name it) and
  the arm asked for;
* the fixture frames the program may name (read from the workcell's scene);
* cosmos's own files (every file of the package and the grammar: path, size and
  modification time, as Python's bytecode cache judges a source) and the libraries
  compiling reads (Lark, numpy, MuJoCo, Pinocchio: :func:`cosmos.user_cache.package_stamp`),
  with Python's version.

A key that does not match, a file that cannot be read or unpickled, or anything but a
plan in it: the program is compiled as if there were no file, and the file is written
anew; a cache that cannot be written only means compiling every time. A plan's arrays
are read back as writable as they were (:class:`cosmos.user_cache.ArrayPickler`).
"""

from __future__ import annotations

import hashlib
import io
import os
import pickle
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cosmos.user_cache import ArrayPickler, package_stamp, user_cache_root, write_whole

if TYPE_CHECKING:
    from cosmos.plan import Plan

FORMAT = b"cosmos-plan-1"
"""This file format's name and version (changed when the layout below changes)."""
PACKAGE_DIR = Path(__file__).resolve().parents[1]
"""The cosmos package, whose files the plan is made by."""
GRAMMAR_FILES = (PACKAGE_DIR / "grammar" / "cosmos.lark", PACKAGE_DIR.parent / "grammar" / "cosmos.lark")
"""The grammar: in a wheel, or beside the package in a source tree (:mod:`cosmos.lang.parse.grammar`)."""
LIBRARIES = ("lark", "numpy", "mujoco", "pinocchio")
"""The installed packages whose versions a plan may depend on (parsing, the foreseen limits)."""
KEY_BYTES = 32


def _file_stamps(directory: Path, into: Any) -> None:
    """Feed ``into`` each file's path, size and modification time under ``directory`` (sorted; no caches)."""
    with os.scandir(directory) as entries:
        listed = sorted(entries, key=lambda entry: entry.name)
    for entry in listed:
        if entry.is_dir(follow_symlinks=False):
            if entry.name != "__pycache__" and not entry.name.startswith("."):
                _file_stamps(Path(entry.path), into)
        elif entry.name.endswith((".pyc", ".tmp")):
            continue
        else:
            stat = entry.stat()
            into.update(f"{entry.path}\0{stat.st_size}\0{stat.st_mtime_ns}\n".encode())


def code_stamp() -> bytes:
    """A hash of what compiles a program: cosmos's files, the grammar, the libraries, Python."""
    digest = hashlib.sha256(FORMAT)
    digest.update(sys.version.encode())
    _file_stamps(PACKAGE_DIR, digest)
    for grammar in GRAMMAR_FILES:
        try:
            stat = grammar.stat()
        except OSError:
            continue
        digest.update(f"{grammar}\0{stat.st_size}\0{stat.st_mtime_ns}\n".encode())
    for library in LIBRARIES:
        digest.update(package_stamp(library).encode() + b"\n")
    return digest.digest()


def plan_key(source: str, file: str, fixtures: dict[str, Any], robot: str | None) -> bytes:
    """The key of the plan of ``source`` (from ``file``, for ``robot``) among ``fixtures``."""
    digest = hashlib.sha256(code_stamp())
    frames = sorted(
        (name, frame.position.tobytes(), frame.rotation.tobytes()) for name, frame in fixtures.items()
    )
    digest.update(repr((file, robot, frames)).encode())
    digest.update(b"\0" + source.encode())
    return digest.digest()


def plan_file(file: str, robot: str | None) -> Path:
    """Where the plan of the program at ``file`` (for ``robot``) is kept: one file per path and arm."""
    name = hashlib.sha256(f"{os.path.abspath(file)}\0{robot}".encode()).hexdigest()[:24]
    return user_cache_root() / "plans" / f"{name}.pickle"


def load_plan(path: Path, key: bytes) -> Plan | None:
    """The plan kept at ``path`` under ``key``; None if there is none, or another, or it cannot be read."""
    from cosmos.plan import Plan

    try:
        data = path.read_bytes()
    except OSError:
        return None
    if len(data) <= KEY_BYTES or data[:KEY_BYTES] != key:
        return None
    try:
        plan = pickle.loads(data[KEY_BYTES:])
    except Exception:  # a damaged file can raise anything while unpickling: compiled again
        return None
    return plan if isinstance(plan, Plan) else None


def keep_plan(path: Path, key: bytes, plan: Plan) -> None:
    """Keep ``plan`` at ``path`` under ``key`` (whole or not at all; not at all if it cannot be written)."""
    stream = io.BytesIO()
    stream.write(key)
    try:
        ArrayPickler(stream, protocol=pickle.HIGHEST_PROTOCOL).dump(plan)
        write_whole(path, stream.getvalue())
    except (OSError, pickle.PicklingError, TypeError, AttributeError):
        return
