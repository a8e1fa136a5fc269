"""Where compiled kernels are kept: one user cache shared by every environment of a cosmos version.

numba's own ``cache=True`` writes next to the source (``__pycache__`` in
site-packages) or into numba's user directory keyed by the source's *path*, so
a second virtual environment of the same version compiles everything again,
and an install whose site-packages and home are read-only cannot import the
kernels at all ("no locator available"). Here the cache is keyed by what
the compiled code depends on:

* the directory (:func:`kernel_directory`): the cosmos version, numba's version,
  the Python version and the CPU (``<user cache>/cosmos/kernels/<key>``, or
  ``$COSMOS_CACHE_DIR/kernels/<key>``);
* inside it, one subdirectory per kernel module named by a hash of the
  module's text and of the cosmos modules it imports (a kernel module's hash
  includes its own imports', since a kernel calling another kernel compiles the
  callee into itself), so two environments with the same sources share every
  file, and a changed source gets its own directory instead of fighting over one. The hash
  is kept in the directory with the size and modification time of each file it was made
  from, and made again only when one of them changed (:class:`_KeptDigests`).

If that directory cannot be written, a private one under the temporary
directory is used (:data:`FALLBACK` says why); if none can, kernels are
compiled in every run, uncached (:func:`make_cache` returns None).
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import pickle
import re
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from types import FunctionType
from typing import Any

import numba
from numba.core import config
from numba.core.caching import CompileResultCacheImpl, FunctionCache, NullCache, _CacheLocator

from cosmos import __version__
from cosmos.jit import loading
from cosmos.user_cache import CACHE_ENV as CACHE_ENV
from cosmos.user_cache import user_cache_root as user_cache_root
from cosmos.user_cache import write_whole

KERNEL_IMPORT = "from cosmos.jit import kernel"
"""The line that makes a module a kernel module (its hash includes its imports' hashes)."""

_COSMOS_IMPORT = re.compile(
    r"^[ \t]*(?:from[ \t]+(cosmos[\w.]*)[ \t]+import[ \t]+(?:\(([^)]*)\)|([\w \t,]+))"
    r"|import[ \t]+(cosmos[\w.]*))",
    re.M,
)


def cpu_name() -> str:
    """The CPU numba compiles for (``NUMBA_CPU_NAME`` if set, else the host's)."""
    from llvmlite import binding

    return str(getattr(config, "CPU_NAME", None) or binding.get_host_cpu_name())


def cache_key() -> str:
    """The part of the cache's path that a compiled kernel depends on besides its source."""
    python = f"py{sys.version_info[0]}{sys.version_info[1]}"
    return f"cosmos-{__version__}-numba-{numba.__version__}-{python}-{cpu_name()}".replace(os.sep, "_")


def fallback_root() -> Path | None:
    """A directory of this user's under the temporary directory (for read-only homes).

    None if there is no temporary directory to write in (``tempfile`` found none).
    """
    uid = os.getuid() if hasattr(os, "getuid") else 0
    try:
        return Path(tempfile.gettempdir()) / f"cosmos-{uid}"
    except FileNotFoundError:
        return None


@functools.cache
def _writable(directory: Path) -> str:
    """The reason kernels cannot be cached in ``directory`` (made if need be); empty if they can."""
    try:
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        if hasattr(os, "getuid") and directory.stat().st_uid != os.getuid():
            return f"{directory} belongs to another user"
        tempfile.TemporaryFile(dir=directory).close()
    except OSError as error:
        return f"{directory}: {error.strerror or error}"
    return ""


@functools.cache
def kernel_directory() -> Path | None:
    """The directory kernels are cached in, or None if no directory can be written.

    The user cache first; if it cannot be written, a private directory under the
    temporary directory (the reason is kept in :data:`FALLBACK`).
    """
    user = user_cache_root() / "kernels" / cache_key()
    reason = _writable(user)
    if not reason:
        return user
    FALLBACK.append(reason)
    root = fallback_root()
    if root is None:
        FALLBACK.append("no temporary directory can be written")
        return None
    temporary = root / "kernels" / cache_key()
    second = _writable(temporary) or _writable(root)  # the shared directory's entry is ours
    if not second:
        return temporary
    FALLBACK.append(second)
    return None


FALLBACK: list[str] = []
"""Why the user cache (and the temporary one) could not be used; empty when it could."""


def _module_file(name: str) -> Path | None:
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
        return None
    return Path(spec.origin)


def _imported_modules(package: str, names: str) -> list[str]:
    """The cosmos modules ``from package import names`` reads: submodules by name, else the package."""
    found = []
    for name in (part.strip().split(" ")[0] for part in names.split(",")):
        if name and _module_file(f"{package}.{name}") is not None:
            found.append(f"{package}.{name}")
    return found or [package]


@functools.cache
def source_digest(module: str) -> str:
    """A hash of ``module``'s text and of the cosmos modules it imports (kernel modules: recursively)."""
    path = _module_file(module)
    if path is None:
        _READ[module] = frozenset()
        return "0" * 16
    read = {path}
    text = path.read_text(encoding="utf-8")
    digest = hashlib.sha256(text.encode())
    for match in _COSMOS_IMPORT.finditer(text):
        package, listed, names, plain = match.groups()
        for name in _imported_modules(package, listed or names) if package else [plain]:
            if name == module or name == "cosmos.jit":
                continue
            imported = _module_file(name)
            if imported is None:
                continue
            is_kernel_module, text_digest = _file_digest(imported)
            if is_kernel_module:
                digest.update(source_digest(name).encode())
                read |= _READ[name]
            else:
                digest.update(text_digest)
                read.add(imported)
    _READ[module] = frozenset(read)
    return digest.hexdigest()[:16]


_READ: dict[str, frozenset[Path]] = {}
"""Per module whose :func:`source_digest` was computed, the files its digest was made from."""


@functools.cache
def _file_digest(path: Path) -> tuple[bool, bytes]:
    """Whether the module at ``path`` is a kernel module, and a hash of its text (read once)."""
    text = path.read_bytes()
    return KERNEL_IMPORT.encode() in text, hashlib.sha256(text).digest()


DIGESTS_FILE = "digests-1.pickle"
"""In the kernel directory: each kernel module's :func:`source_digest`, with what it was made from."""
MAX_DIGESTS = 2000
"""More entries than this in the file (old sources piling up): start it again."""


def _stamp(path: str) -> tuple[int, int] | None:
    """A file's or directory's size and modification time (as Python's bytecode cache judges a source)."""
    try:
        stat = os.stat(path)
    except OSError:
        return None
    return stat.st_size, stat.st_mtime_ns


class _KeptDigests:
    """The kernel modules' digests kept in :data:`DIGESTS_FILE`, with the stamps of what each was made from.

    Hashing a kernel module's text and the texts of the cosmos modules it imports (and finding
    them) took 4-5 ms of every warm run for the 7 modules of ``peg_in_hole.cos``'s kernels; a
    digest whose files (and their directories: a module added to a package) all have the size
    and modification time they had is read back instead. An entry is keyed by the module's name
    and its file, so the environments sharing the kernel directory keep theirs apart.
    """

    def __init__(self, path: Path):
        self.path = path
        try:
            entries = pickle.loads(path.read_bytes())
        except Exception:  # missing, or damaged (unpickling can raise anything): computed again
            entries = {}
        self.entries: dict[tuple[str, str], tuple[str, tuple[tuple[str, Any], ...]]] = (
            entries if isinstance(entries, dict) else {}
        )

    @functools.cache  # noqa: B019 - one instance per kernel directory, for the process
    def digest(self, module: str, file: str) -> str:
        """:func:`source_digest` of ``module`` (whose file is ``file``): kept, else computed and kept."""
        kept = self.entries.get((module, file))
        if kept is not None and all(_stamp(path) == stamp for path, stamp in kept[1]):
            return kept[0]
        digest = source_digest(module)
        read = _READ.get(module, frozenset())
        watched = sorted(str(path) for path in {*read, *(path.parent for path in read)})
        if len(self.entries) >= MAX_DIGESTS:
            self.entries.clear()
        self.entries[module, file] = (digest, tuple((path, _stamp(path)) for path in watched))
        try:
            write_whole(self.path, pickle.dumps(self.entries, protocol=pickle.HIGHEST_PROTOCOL))
        except OSError:
            pass  # a cache that cannot be written: hashed again next time
        return digest


@functools.cache
def _kept_digests(directory: Path) -> _KeptDigests:
    return _KeptDigests(directory / DIGESTS_FILE)


def kept_source_digest(module: str, file: str, directory: Path) -> str:
    """:func:`source_digest` of ``module`` (from ``file``), kept in the kernel ``directory`` across runs."""
    return _kept_digests(directory).digest(module, file)


class KernelLocator(_CacheLocator):
    """numba's cache locator for cosmos kernels: :func:`kernel_directory` / ``<module>-<digest>``."""

    def __init__(self, function: FunctionType, directory: Path):
        self._py_file = function.__code__.co_filename
        self._lineno = function.__code__.co_firstlineno
        module = function.__module__
        self._digest = kept_source_digest(module, self._py_file, directory)
        self._path = directory / f"{module}-{self._digest}"

    def ensure_cache_path(self) -> None:
        """Make the module's directory (its parent is known to be writable)."""
        self._path.mkdir(mode=0o700, exist_ok=True)

    def get_cache_path(self) -> str:
        """The module's directory."""
        return str(self._path)

    def get_source_stamp(self) -> str:
        """The source's hash (it is also in the path: a stale entry is never found)."""
        return self._digest

    def get_disambiguator(self) -> str:
        """The function's first line, as numba's own locators use."""
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func: FunctionType, py_file: str) -> KernelLocator | None:
        """A locator in :func:`kernel_directory`, or None if there is none."""
        directory = kernel_directory()
        if directory is None:
            return None
        locator = cls(py_func, directory)
        try:
            locator.ensure_cache_path()
        except OSError:
            return None
        return locator


class _KernelCacheImpl(CompileResultCacheImpl):
    _locator_classes = [KernelLocator]

    def rebuild(self, target_context: Any, payload: Any) -> Any:
        """Numba's rebuild of a cached kernel, its library made by :func:`loading.library_from_object`."""
        if not loading.ENABLED:
            return super().rebuild(target_context, payload)
        codegen = target_context.codegen()
        codegen.unserialize_library = functools.partial(loading.library_from_object, codegen)
        try:
            return super().rebuild(target_context, payload)
        finally:
            del codegen.unserialize_library  # numba's own again, for what it compiles


class KernelCache(FunctionCache):
    """numba's function cache in :func:`kernel_directory`.

    A kernel found in the cache is loaded without first loading every typing and
    lowering registry numba has (``refresh``: a third of a second, SciPy's
    ``linalg`` among them), which only compiling needs; the compiler loads them
    itself when a kernel has to be compiled. What loading does besides is
    :mod:`cosmos.jit.loading`'s.
    """

    _impl_class = _KernelCacheImpl

    def __init__(self, py_func: Callable[..., Any]):
        super().__init__(py_func)
        if not loading.ENABLED:
            return
        self._cache_file = loading.KernelFile(
            cache_path=self._cache_path,
            filename_base=self._impl.filename_base,
            source_stamp=self._impl.locator.get_source_stamp(),
        )

    def load_overload(self, sig, target_context):
        """Load the compiled kernel for ``sig`` if it is cached (None if not)."""
        # What a loaded kernel links against (array allocation), itself kept in the cache.
        loading.initialize_runtime(target_context, kernel_directory())
        return self._load_overload(sig, target_context)

    def _index_key(self, sig: Any, codegen: Any) -> Any:
        """The key of ``sig`` in the kernel's index (numba's), the codegen's description asked once."""
        return super()._index_key(sig, _described(codegen))


class _CodegenDescription:
    """What numba's index key asks of a codegen (``magic_tuple``: an LLVM call per kernel), kept."""

    def __init__(self, codegen: Any):
        self._magic = codegen.magic_tuple()

    def magic_tuple(self) -> Any:
        """The codegen's target triple, CPU name and features, as numba's codegen gives them."""
        return self._magic


@functools.cache
def _described(codegen: Any) -> _CodegenDescription:
    return _CodegenDescription(codegen)


class LazyKernelCache:
    """A kernel's :class:`KernelCache`, made when numba first asks anything of it.

    Making one hashes the kernel module's source and the cosmos modules it imports and makes
    the module's directory: 6 ms at import for cosmos's 74 kernels, of which a run loads 15 to 25.
    If it cannot be made (the directory went away), the kernel is compiled uncached.
    """

    def __init__(self, function: Callable[..., Any]):
        self._function = function
        self._made: KernelCache | NullCache | None = None

    def made(self) -> KernelCache | NullCache:
        """The kernel's cache, made now if it is not yet."""
        if self._made is None:
            try:  # numba asks KernelLocator.from_function, which reads kernel_directory() again
                self._made = KernelCache(self._function)
            except RuntimeError:  # no locator: the directory went away
                self._made = NullCache()
        return self._made

    def __getattr__(self, name: str) -> Any:
        return getattr(self.made(), name)


def make_cache(function: Callable[..., Any]) -> LazyKernelCache | None:
    """The cache for ``function`` (made when first used), or None if no directory can be written."""
    if kernel_directory() is None:
        return None
    return LazyKernelCache(function)
