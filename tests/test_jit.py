"""The kernel cache: shared by environments, keyed by what compiled code depends on, never fatal."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba.core import event

import cosmos.jit
from cosmos.jit import cache, kernel, notice
from cosmos.runtime.kernels import servo as servo_kernel

ROOT = Path(__file__).resolve().parents[1]


def _clean_env(**changes: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("COSMOS_CACHE_DIR", "XDG_CACHE_HOME")}
    env.update(changes)
    return env


def test_read_only_home_and_install_run_a_program(tmp_path: Path) -> None:
    """With no writable home (a system or container install), ``cosmos run`` used to die at import
    ("cannot cache function ...: no locator available"); it must run, caching under the temporary
    directory and saying so. The temporary cache is this process's (linked), so nothing recompiles.
    The package runs from a copy in which nothing can be written beside the source (each of its
    directories holds a file named ``__pycache__``, as an install the user cannot write): catches
    anything (bytecode aside, which Python skips) written next to the source, or needed there."""
    blocker = tmp_path / "not_a_directory"
    blocker.write_text("")
    temp = tmp_path / "tmp"
    uid = os.getuid() if hasattr(os, "getuid") else 0
    (temp / f"cosmos-{uid}").mkdir(parents=True)
    warm = cache.kernel_directory()
    assert warm is not None
    (temp / f"cosmos-{uid}" / "kernels").symlink_to(warm.parent, target_is_directory=True)
    site = tmp_path / "site"
    shutil.copytree(ROOT / "cosmos", site / "cosmos", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "grammar", site / "grammar")
    for directory in [site, *(path for path in site.rglob("*") if path.is_dir())]:
        (directory / "__pycache__").write_text("")
    before = sorted(site.rglob("*"))
    env = _clean_env(HOME=str(blocker / "home"), TMPDIR=str(temp), PYTHONPATH=str(site))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "cosmos",
            "run",
            str(ROOT / "programs" / "hello.cos"),
            "--log",
            str(tmp_path / "a.mcap"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
        cwd=tmp_path,
    )
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert "cannot keep compiled kernels in the user cache" in result.stderr
    assert str(temp / f"cosmos-{uid}" / "kernels") in result.stderr
    assert (tmp_path / "a.mcap").stat().st_size > 0
    assert sorted(site.rglob("*")) == before


def test_kernels_are_not_cached_next_to_the_source() -> None:
    """A read-only site-packages must not matter: numba's in-tree ``__pycache__`` is not used."""
    path = Path(servo_kernel.servo_tick._cache.cache_path)
    directory = cache.kernel_directory()
    assert directory is not None and path.parent == directory
    assert Path(servo_kernel.__file__).parent not in path.parents


def test_a_second_environment_shares_the_cache(tmp_path: Path) -> None:
    """numba keys its cache by the source's path, so a second virtual environment of the same version
    compiled every kernel again; the same sources elsewhere must give the same cache directory."""
    copy = tmp_path / "elsewhere"
    shutil.copytree(ROOT / "cosmos", copy / "cosmos", ignore=shutil.ignore_patterns("__pycache__"))
    probe = (
        "import cosmos, cosmos.runtime.kernels.servo as k; "
        f"assert cosmos.__file__.startswith({str(copy)!r}), cosmos.__file__; "
        "print(k.servo_tick._cache.cache_path)"
    )
    env = _clean_env(PYTHONPATH=str(copy), COSMOS_CACHE_DIR=str(cache.user_cache_root()))
    result = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=300, env=env, cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == servo_kernel.servo_tick._cache.cache_path


def test_digest_follows_imported_kernel_modules(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A kernel calling a kernel of another module compiles the callee into itself: when the callee's
    module changes, the caller's cached code is stale, so the caller's digest must change too
    (numba's own cache keys a function by its own file only). A module imported by a plain module is not
    followed (else any edit anywhere would recompile everything)."""
    files = {
        "cosmos.fake.caller": (
            f"{cache.KERNEL_IMPORT}\nfrom cosmos.fake import callee as c\nfrom cosmos.fake.plain import X\n"
        ),
        "cosmos.fake.callee": f"{cache.KERNEL_IMPORT}\nY = 1\n",
        "cosmos.fake.plain": "from cosmos.fake.far import Z\nX = 2\n",
        "cosmos.fake.far": "Z = 3\n",
    }
    for name, text in files.items():
        (tmp_path / f"{name}.py").write_text(text)
    monkeypatch.setattr(
        cache, "_module_file", lambda name: tmp_path / f"{name}.py" if name in files else None
    )

    def digest() -> str:
        cache.source_digest.cache_clear()
        cache._file_digest.cache_clear()
        return cache.source_digest("cosmos.fake.caller")

    before = digest()
    assert digest() == before
    for name, edited in (("cosmos.fake.callee", "Y = 2\n"), ("cosmos.fake.plain", "X = 5\n")):
        (tmp_path / f"{name}.py").write_text(files[name] + edited)
        assert digest() != before, name
        (tmp_path / f"{name}.py").write_text(files[name])
        assert digest() == before
    (tmp_path / "cosmos.fake.far.py").write_text("Z = 4\n")
    assert digest() == before
    cache.source_digest.cache_clear()
    cache._file_digest.cache_clear()


def test_kept_digests_follow_the_sources(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a digest read back from the kernel directory after a source it was made from changed
    (the kernel's module, a kernel module it imports, a plain module it imports, or a module added
    where a name was imported): a stale kernel would be loaded. And a damaged file failing the run."""
    sources = tmp_path / "sources"
    sources.mkdir()
    files = {
        "cosmos.fake.caller": (
            f"{cache.KERNEL_IMPORT}\nfrom cosmos.fake import callee, plain\nfrom cosmos.fake.plain import X\n"
        ),
        "cosmos.fake.callee": f"{cache.KERNEL_IMPORT}\nY = 1\n",
        "cosmos.fake.plain": "X = 2\n",
    }
    for name, text in files.items():
        (sources / f"{name}.py").write_text(text)
    monkeypatch.setattr(
        cache,
        "_module_file",
        lambda name: sources / f"{name}.py" if (sources / f"{name}.py").exists() else None,
    )
    directory = tmp_path / "kernels"
    directory.mkdir()
    caller = str(sources / "cosmos.fake.caller.py")

    def computed() -> str:
        cache.source_digest.cache_clear()
        cache._file_digest.cache_clear()
        return cache.source_digest("cosmos.fake.caller")

    def kept() -> str:  # as a new process reads it
        cache._kept_digests.cache_clear()
        if cache.source_digest is not None:
            cache.source_digest.cache_clear()
            cache._file_digest.cache_clear()
        return cache.kept_source_digest("cosmos.fake.caller", caller, directory)

    try:
        assert kept() == computed()
        assert (directory / cache.DIGESTS_FILE).is_file()
        monkeypatch.setattr(cache, "source_digest", None)  # read back, not computed
        first = kept()
        monkeypatch.undo()
        monkeypatch.setattr(
            cache,
            "_module_file",
            lambda name: sources / f"{name}.py" if (sources / f"{name}.py").exists() else None,
        )
        for name, edited in (
            ("cosmos.fake.callee", "Y = 22\n"),
            ("cosmos.fake.plain", "X = 25\n"),
            ("cosmos.fake.caller", "Z = 3\n"),
        ):
            (sources / f"{name}.py").write_text(files[name] + edited)
            assert kept() == computed() != first, name
            (sources / f"{name}.py").write_text(files[name])
        before = kept()
        (sources / "cosmos.fake.plain.X.py").write_text("W = 1\n")  # the name imported is now a module
        assert kept() == computed() != before
        (directory / cache.DIGESTS_FILE).write_bytes(b"\x80\x05damaged")
        assert kept() == computed()
    finally:
        cache.source_digest.cache_clear()
        cache._file_digest.cache_clear()
        cache._kept_digests.cache_clear()


def test_no_temporary_directory_at_all_means_no_cache_not_a_crash(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With the home, site-packages and every temporary directory read-only, ``cosmos run`` died at
    import with ``FileNotFoundError: No usable temporary directory found`` (``tempfile.gettempdir``
    in the fallback): the cache must be None with both reasons kept, so kernels compile uncached."""
    blocker = tmp_path / "not_a_directory"
    blocker.write_text("")
    monkeypatch.setattr(cache, "user_cache_root", lambda: blocker / "cache")

    def no_temporary_directory() -> str:
        raise FileNotFoundError(2, "No usable temporary directory found")

    monkeypatch.setattr(cache.tempfile, "gettempdir", no_temporary_directory)
    monkeypatch.setattr(cache, "FALLBACK", [])
    cache.kernel_directory.cache_clear()
    cache._writable.cache_clear()
    try:
        assert cache.fallback_root() is None
        assert cache.kernel_directory() is None
        assert cache.FALLBACK[0].startswith(str(blocker / "cache"))
        assert cache.FALLBACK[1] == "no temporary directory can be written"
    finally:
        cache.kernel_directory.cache_clear()
        cache._writable.cache_clear()


def test_without_any_cache_kernels_compile_and_run(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """If nothing can be written, kernels must still work (compiled each run) and the user must be
    told why and what to do; a compilation must be announced at once, naming the cosmos part."""
    monkeypatch.setattr(cache, "kernel_directory", lambda: None)
    monkeypatch.setattr(
        cache, "FALLBACK", ["/home/x: Read-only file system", "/tmp/cosmos-0: Read-only file system"]
    )
    monkeypatch.setattr(cosmos.jit, "_warned", [])

    def scaled_sum(values: np.ndarray, factor: float) -> float:
        total = 0.0
        for value in values:
            total += value * factor
        return total

    scaled_sum.__module__ = "cosmos.runtime.fake"
    listener = notice.CompileNotice("nowhere", summary_at_exit=False)
    event.unregister("numba:compile", cosmos.jit._NOTICE)  # this process's own notice stays quiet
    try:
        with event.install_listener("numba:compile", listener):
            compiled = kernel(scaled_sum)
            assert compiled._cache.__class__.__name__ == "NullCache"
            assert compiled(np.arange(4.0), 0.5) == 3.0
    finally:
        event.register("numba:compile", cosmos.jit._NOTICE)
    err = capsys.readouterr().err
    assert "cannot keep compiled kernels anywhere" in err and "COSMOS_CACHE_DIR" in err
    assert listener.announced == {"the controller"} and listener.compiled == 1
    assert "compiling the controller for this machine, once: about 15 s (kept in nowhere)" in err


def test_read_only_arguments_compile_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """numba compiles a kernel again for a read-only array where it saw a writable one (a plan's
    rotation is read-only, the controller's own copy is not): the controller's refold was compiled
    twice on every first run. Named read-only arguments must compile once and serve both."""
    monkeypatch.setattr(cache, "kernel_directory", lambda: None)

    def doubled_into(values: np.ndarray, out: np.ndarray) -> None:
        for i in range(values.shape[0]):
            out[i] = 2.0 * values[i]

    compiled = kernel(read_only=("values",))(doubled_into)
    out = np.zeros(3)
    writable = np.arange(3.0)
    frozen = np.arange(3.0)
    frozen.flags.writeable = False
    compiled(writable, out)
    compiled(frozen, out)
    np.testing.assert_array_equal(out, (0.0, 2.0, 4.0))
    assert len(compiled.signatures) == 1
    assert compiled.signatures[0][0].mutable is False
    # Both kinds are then dispatched without Python: no new compilation is even asked for.
    asked = []
    compile_all = compiled._compile_for_args
    monkeypatch.setattr(compiled, "_compile_for_args", lambda *args: asked.append(args) or compile_all(*args))
    compiled(writable, out)
    compiled(frozen, out)
    assert asked == []


def test_every_kernel_uses_the_cosmos_decorator() -> None:
    """A kernel decorated with numba's own ``njit(cache=True)`` caches next to its source: a read-only
    install dies at import ("no locator available") and every environment compiles it again."""
    offenders = []
    for path in sorted((ROOT / "cosmos").rglob("*.py")):
        if path.parent.name == "jit" and path.parent.parent.name == "cosmos":
            continue
        text = path.read_text(encoding="utf-8")
        if re.search(r"^\s*@(numba\.)?(njit|jit)\b|^\s*from numba import .*\b(njit|jit)\b", text, re.M):
            offenders.append(str(path.relative_to(ROOT)))
    assert offenders == [], f"use cosmos.jit.kernel in {offenders}"


def test_declared_signatures_compile_at_the_first_call_and_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """A kernel with a declared signature was compiled (or loaded from the cache) at import: a warm
    run loaded the linear-algebra kernels it only ever calls from other kernels (9 loads, about
    50 ms). Catches that, and a second compilation for arguments that convert to the declared
    signature (a contiguous, a strided and a read-only array; from Python and from a kernel)."""
    monkeypatch.setattr(cache, "kernel_directory", lambda: None)
    from numba.core import types

    any_vector = types.Array(types.float64, 1, "A", readonly=True)

    def total(values: np.ndarray) -> float:
        acc = 0.0
        for value in values:
            acc += value
        return acc

    declared = kernel(types.float64(any_vector))(total)
    assert declared.signatures == []  # nothing compiled yet

    def twice_total(values: np.ndarray) -> float:
        return 2.0 * declared(values)

    caller = kernel(twice_total)
    assert caller(np.arange(4.0)) == 12.0  # the declared kernel compiled inside the caller
    frozen = np.arange(6.0)
    frozen.flags.writeable = False
    assert declared(np.arange(4.0)) == 6.0
    assert declared(frozen[::2]) == 6.0
    assert declared(frozen) == 15.0
    assert len(declared.signatures) == 1 and declared.signatures[0] == (any_vector,)
    with pytest.raises(TypeError):
        declared(np.arange(4))  # integers do not convert to the declared float64 array


def test_a_kernel_declared_beside_is_compiled_by_a_helper_and_loaded_here(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """On a first run the servo tick (a third of the compile time) is compiled by a helper process
    while this one compiles the kernels needed before it. Catches no helper started, a helper that
    writes somewhere this process does not look (it would compile the kernel again here), and this
    process not waiting for the helper (it would compile the kernel itself meanwhile)."""
    from cosmos.jit import beside

    directory = tmp_path / "cache" / "kernels" / cache.cache_key()
    directory.mkdir(parents=True)
    source = tmp_path / "src"
    source.mkdir()
    (source / "beside_probe.py").write_text(
        "from numba.core import types\n\nfrom cosmos.jit import kernel\n\n\n"
        "@kernel(types.float64(types.float64), beside=True)\n"
        "def doubled(x):\n    return 2.0 * x\n",
        encoding="utf-8",
    )
    monkeypatch.setattr(cache, "kernel_directory", lambda: directory)
    monkeypatch.setattr(beside, "_registered", [])
    monkeypatch.setattr(beside, "_helpers", {})
    monkeypatch.setattr(beside, "core_free", lambda: True)  # the test machine may be busy
    monkeypatch.syspath_prepend(str(source))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(source), os.environ.get("PYTHONPATH", "")]))
    monkeypatch.setenv("COSMOS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv(beside.HELPER_ENV, raising=False)
    monkeypatch.delitem(sys.modules, "beside_probe", raising=False)
    import beside_probe  # type: ignore[import-not-found]

    compiled_here: list[str] = []

    class Listener(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            compiled_here.append(ev.data["dispatcher"].py_func.__name__)

        def on_end(self, ev: event.Event) -> None:
            pass

    listener = Listener()
    event.register("numba:compile", listener)
    try:
        beside.start(directory)
        assert beside.started() == 1
        assert beside_probe.doubled(3.0) == 6.0  # waits for the helper, then loads its work
    finally:
        event.unregister("numba:compile", listener)
        sys.modules.pop("beside_probe", None)
    assert "doubled" not in compiled_here
    assert sum(beside_probe.doubled._cache_hits.values()) == 1
    assert beside.started() == 0


def test_a_kernels_cache_is_made_when_first_used(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches every kernel's cache made at import (its module's source hashed, its directory made:
    6 ms of every start-up for the 74 kernels, of which a run loads 15 to 25), and a kernel's cache
    made late but not used: the compiled kernel must be saved to and found in its directory."""
    monkeypatch.setattr(cache, "kernel_directory", lambda: tmp_path)
    monkeypatch.setattr(cosmos.jit, "_warned", [True])

    def halved(value: float) -> float:
        return value / 2.0

    compiled = kernel(halved)
    lazy = compiled._cache
    assert isinstance(lazy, cache.LazyKernelCache) and lazy._made is None
    assert list(tmp_path.iterdir()) == []
    assert compiled(3.0) == 1.5
    assert isinstance(lazy._made, cache.KernelCache)
    assert Path(lazy.cache_path).parent == tmp_path
    assert any(path.suffix == ".nbi" for path in Path(lazy.cache_path).iterdir())
    again = kernel(halved)
    assert again(5.0) == 2.5 and again.stats.cache_hits
