"""``cosmos run`` reads a program's plan back from the user cache instead of compiling it again."""

from __future__ import annotations

import dataclasses
import enum
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from cosmos.commands import plan_cache
from cosmos.commands.run import compile_file
from cosmos.lang import compile_program, read_program
from cosmos.runtime.foresight import with_foreseen_limits
from cosmos.user_cache import ArrayPickler
from cosmos.workcell import fixture_frames

PROGRAMS = sorted((Path(__file__).resolve().parents[1] / "programs").glob("*.cos"))


@pytest.fixture()
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def assert_same(read: Any, compiled: Any, where: str = "plan") -> None:
    """``read`` is ``compiled`` value for value: types, fields, floats to the bit, arrays with their flags."""
    assert type(read) is type(compiled), where
    if isinstance(compiled, np.ndarray):
        assert (read.dtype, read.shape, read.strides) == (compiled.dtype, compiled.shape, compiled.strides), (
            where
        )
        assert read.flags.writeable == compiled.flags.writeable, where
        assert read.tobytes() == compiled.tobytes(), where
    elif isinstance(compiled, float):
        assert math.copysign(1.0, read) == math.copysign(1.0, compiled), where
        assert read == compiled or (math.isnan(read) and math.isnan(compiled)), where
    elif isinstance(compiled, enum.Enum):
        assert read is compiled, where
    elif isinstance(compiled, (list, tuple)):
        assert len(read) == len(compiled), where
        for i, (a, b) in enumerate(zip(read, compiled, strict=True)):
            assert_same(a, b, f"{where}[{i}]")
    elif isinstance(compiled, dict):
        assert list(read) == list(compiled), where
        for name in compiled:
            assert_same(read[name], compiled[name], f"{where}[{name!r}]")
    elif dataclasses.is_dataclass(compiled):
        for field in dataclasses.fields(compiled):
            assert_same(getattr(read, field.name), getattr(compiled, field.name), f"{where}.{field.name}")
    elif isinstance(compiled, (frozenset, set)):
        assert read == compiled, where
    else:
        assert isinstance(compiled, (str, bytes, int, bool, type(None))), f"{where}: {type(compiled)}"
        assert read == compiled, where


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda path: path.stem)
def test_a_kept_plan_is_the_compilers(cache_dir: Path, program: Path) -> None:
    """Catches a plan read back other than the compiler makes it: a field lost or changed by pickling,
    a read-only array come back writable (numba would compile its kernels anew for it)."""
    source = read_program(program)
    compiled = with_foreseen_limits(compile_program(source, str(program), fixture_frames()))
    first = compile_file(program)
    assert plan_cache.plan_file(str(program), None).is_file()
    again = compile_file(program)
    assert_same(first, compiled)
    assert_same(again, compiled)


def test_a_damaged_file_is_compiled_again(cache_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Catches a truncated, foreign or stale cache file failing the run (a traceback) or giving its plan."""
    program = PROGRAMS[0]
    compiled = compile_file(program)
    path = plan_cache.plan_file(str(program), None)
    whole = path.read_bytes()
    key = whole[: plan_cache.KEY_BYTES]
    for damage in (whole[:-20], key + b"not a pickle", key + b"\x80\x05K\x01.", b"", bytes(40) + whole[40:]):
        path.write_bytes(damage)
        assert_same(compile_file(program), compiled)
        assert path.read_bytes() == whole  # written anew
    assert capsys.readouterr().err == ""


def test_an_unwritable_cache_only_compiles(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a cache directory that cannot be made failing the run or saying more than nothing."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(blocker / "cache"))  # under a file: cannot be made
    program = PROGRAMS[0]
    assert_same(
        compile_file(program),
        with_foreseen_limits(compile_program(read_program(program), str(program), fixture_frames())),
    )


def test_the_key_names_what_the_plan_is_made_from(tmp_path: Path) -> None:
    """Catches a key blind to the program's text, its path, the arm, a fixture or cosmos's own files
    (each would give the plan of another program, or of the old code)."""
    frames = fixture_frames()
    key = plan_cache.plan_key("MOVE BY (0, 0, 1 mm)\n", "a.cos", frames, None)
    assert key == plan_cache.plan_key("MOVE BY (0, 0, 1 mm)\n", "a.cos", fixture_frames(), None)
    assert key != plan_cache.plan_key("MOVE BY (0, 0, 2 mm)\n", "a.cos", frames, None)
    assert key != plan_cache.plan_key("MOVE BY (0, 0, 1 mm)\n", "b.cos", frames, None)
    assert key != plan_cache.plan_key("MOVE BY (0, 0, 1 mm)\n", "a.cos", frames, "panda")
    moved = dict(frames)
    hole = frames["hole"]
    moved["hole"] = dataclasses.replace(hole, position=hole.position + np.array([0.0, 0.0, 1e-6]))
    assert key != plan_cache.plan_key("MOVE BY (0, 0, 1 mm)\n", "a.cos", moved, None)

    package = tmp_path / "package"
    (package / "lang").mkdir(parents=True)
    module = package / "lang" / "compiler.py"
    module.write_text("A = 1\n")

    def stamp() -> bytes:
        digest = plan_cache.hashlib.sha256()
        plan_cache._file_stamps(package, digest)
        return digest.digest()

    before = stamp()
    (package / "lang" / "__pycache__").mkdir()
    (package / "lang" / "__pycache__" / "compiler.cpython-311.pyc").write_bytes(b"x")
    assert stamp() == before  # bytecode is not the source
    module.write_text("A = 2\n")
    os.utime(module, ns=(1, 1))
    assert stamp() != before


def test_a_run_from_a_kept_plan_imports_no_parser(cache_dir: Path) -> None:
    """Catches `cosmos run` importing Lark and the compiler though the plan is kept (50 ms of start-up)."""
    program = PROGRAMS[0]
    compile_file(program)
    code = (
        "import sys; from pathlib import Path; from cosmos.commands.run import compile_file; "
        f"compile_file(Path({str(program)!r})); "
        "print(sorted(m for m in sys.modules if m == 'lark' or m.startswith('cosmos.lang.compile')))"
    )
    env = dict(os.environ, COSMOS_CACHE_DIR=str(cache_dir))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert done.stdout.strip() == "[]"


def test_arrays_come_back_as_writable_as_they_were() -> None:
    """Catches numpy's own pickle reading every array back read-only (protocol 5) or writable (older
    protocols): a kernel typed for the other kind would be compiled again in the run."""
    import io
    import pickle

    read_only = np.arange(6.0).reshape(2, 3)
    read_only.setflags(write=False)
    arrays = (
        read_only,
        np.arange(4.0),
        np.asfortranarray(np.eye(3)),
        np.zeros((0, 3)),
        np.array([True, False]),
    )
    stream = io.BytesIO()
    ArrayPickler(stream, protocol=pickle.HIGHEST_PROTOCOL).dump(arrays)
    for read, kept in zip(pickle.loads(stream.getvalue()), arrays, strict=True):
        assert_same(read, kept, "array")
        assert read.flags.owndata
