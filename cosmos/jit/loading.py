"""Loading a cached kernel: only what running it needs.

numba's cache loads a kernel in three steps that a run whose kernels are all cached
does not need (0.2 s of a warm ``cosmos run``, over the kernels it loads):

* it rebuilds the environment of every function compiled into the kernel, numba's own
  implementations among them, importing each one's module (``numba.np.arrayobj``,
  ``numba.np.linalg`` ...: a tenth of a second of imports that only compiling needs);
  only object-mode code reads an environment's namespace, and cosmos's kernels have
  none (:func:`rebuilt_environment`);
* it parses the kernel's LLVM bitcode, kept so that a kernel compiled later can
  inline it (:func:`library_from_object`: parsed when a compilation first links it);
* it lists the symbols the kernel defines by walking that bitcode, calls into LLVM
  for each symbol; the compiled object's own symbol table names the same ones
  (:func:`object_symbols`: ELF; other formats are walked as numba walks them).

And before the first kernel, numba compiles its runtime (NRT: reference counts, array
allocation) from LLVM IR in every process (20-50 ms); it is kept beside the kernels
(:func:`initialize_runtime`).

All of this reaches into numba's private loading code, so it is used only with the numba
versions it was checked against (:data:`CHECKED_NUMBA`, ``tests/test_jit_loading.py``);
with any other, kernels load as numba loads them (:data:`ENABLED` is False): slower, not wrong.
"""

from __future__ import annotations

import functools
import importlib
import io
import pickle
import struct
import sys
from pathlib import Path
from typing import Any

import llvmlite.binding as ll
import numba
from numba.core import config
from numba.core.caching import IndexDataCacheFile
from numba.core.compiler_lock import global_compiler_lock
from numba.core.environment import Environment, lookup_environment
from numba.core.runtime import _nrt_python, nrt, nrtdynmod  # type: ignore[attr-defined]

from cosmos.user_cache import write_whole

CHECKED_NUMBA = ((0, 68),)
"""numba's (major, minor) versions whose private loading code this module follows."""
ENABLED = tuple(int(part) for part in numba.__version__.split(".")[:2]) in CHECKED_NUMBA
"""This numba is one of :data:`CHECKED_NUMBA`: kernels load through this module."""

RUNTIME_FILE = "numba-runtime.bin"
"""numba's runtime library, compiled: the object's length (8 bytes), the object, its bitcode."""

_ELF_HEADER = struct.Struct("<4sBB")  # magic, class (2: 64-bit), data (1: little-endian)
_ELF_SECTION_TABLE = struct.Struct("<Q")  # e_shoff, at 0x28
_ELF_SECTION_COUNT = struct.Struct("<HH")  # e_shentsize, e_shnum, at 0x3A
_ELF_SECTION = struct.Struct("<IIQQQQIIQQ")  # name, type, flags, addr, offset, size, link, info, ...
_ELF_SYMBOL = struct.Struct("<IBBHQQ")  # name, info, other, section, value, size
_SYMTAB = 2
_NOT_A_SYMBOL = (3, 4)  # STT_SECTION, STT_FILE


def rebuilt_environment(module: str, consts: list[Any], name: str) -> Environment:
    """Numba's ``_rebuild_env``, giving numba's modules not yet imported a namespace of their name alone.

    numba's own check of an environment (``can_cache``) reads only ``__name__``.
    """
    found = lookup_environment(name)
    if found is not None:
        return found
    loaded = sys.modules.get(module)
    if loaded is None and not module.startswith("numba."):
        loaded = importlib.import_module(module)
    built = Environment(loaded.__dict__ if loaded is not None else {"__name__": module})
    built.consts[:] = consts
    built.env_name = name
    Environment._memo[name] = built
    return built


class _KernelUnpickler(pickle.Unpickler):
    def find_class(self, module: str, name: str) -> Any:
        if module == "numba.core.environment" and name == "_rebuild_env":
            return rebuilt_environment
        return super().find_class(module, name)


class KernelFile(IndexDataCacheFile):
    """numba's index and data files of one kernel, its data read with :func:`rebuilt_environment`."""

    def _load_data(self, name: str) -> Any:
        with open(self._data_path(name), "rb") as file:
            return _KernelUnpickler(io.BytesIO(file.read())).load()


def object_symbols(object_code: bytes) -> set[str] | None:
    """The names of the symbols a 64-bit little-endian ELF object defines; None for another format."""
    if len(object_code) < 0x40:
        return None
    magic, bits, order = _ELF_HEADER.unpack_from(object_code, 0)
    if magic != b"\x7fELF" or bits != 2 or order != 1:
        return None
    (offset,) = _ELF_SECTION_TABLE.unpack_from(object_code, 0x28)
    entry_size, count = _ELF_SECTION_COUNT.unpack_from(object_code, 0x3A)
    sections = [_ELF_SECTION.unpack_from(object_code, offset + i * entry_size) for i in range(count)]
    names: set[str] = set()
    for section in sections:
        if section[1] != _SYMTAB:
            continue
        strings = sections[section[6]]
        text = object_code[strings[4] : strings[4] + strings[5]]
        table = object_code[section[4] : section[4] + section[5]]
        for name, info, _, where, _, _ in _ELF_SYMBOL.iter_unpack(table):
            if name and where and info & 0xF not in _NOT_A_SYMBOL:
                names.add(text[name : text.index(b"\0", name)].decode())
    return names


def _module_for_linking(library: Any, bitcode: bytes) -> Any:
    if library._shared_module is None:
        library._shared_module = ll.parse_bitcode(bitcode)
    return library._shared_module


def library_from_object(codegen: Any, serialized: tuple[str, str, Any]) -> Any:
    """Numba's ``CPUCodeLibrary._unserialize``, its bitcode parsed when first linked, not now."""
    name, kind, data = serialized
    if kind != "object":
        return type(codegen).unserialize_library(codegen, serialized)
    object_code, bitcode = data
    symbols = object_symbols(object_code)
    library = codegen.create_library(name)
    library.enable_object_caching()
    library._set_compiled_object(object_code)
    library._get_module_for_linking = functools.partial(_module_for_linking, library, bitcode)
    library._finalize_final_module()
    if symbols is None:  # not ELF: as numba does
        codegen._engine._load_defined_symbols(library._get_module_for_linking())
    else:
        codegen._engine._defined_symbols |= symbols
    return library


def _compile_runtime(context: Any) -> tuple[Any, bytes, bytes]:
    """Numba's ``compile_nrt_functions``, keeping the compiled object: the library, object, bitcode."""
    with global_compiler_lock:
        ir_module, library = nrtdynmod.create_nrt_module(context)
        library.enable_object_caching()
        library.add_ir_module(ir_module)
        library.finalize()
        _, _, (object_code, bitcode) = library.serialize_using_object_code()
    return library, object_code, bitcode


def _read_runtime(path: Path) -> tuple[bytes, bytes] | None:
    try:
        blob = path.read_bytes()
    except OSError:
        return None
    if len(blob) < 8:
        return None
    (length,) = struct.unpack_from("<Q", blob, 0)
    if length > len(blob) - 8:
        return None
    return blob[8 : 8 + length], blob[8 + length :]


def _write_runtime(path: Path, object_code: bytes, bitcode: bytes) -> None:
    """Keep the compiled runtime in ``path`` if it can be written (whole or not at all)."""
    try:
        write_whole(path, struct.pack("<Q", len(object_code)) + object_code + bitcode)
    except OSError:
        return


def initialize_runtime(context: Any, directory: Path | None) -> None:
    """Numba's ``rtsys.initialize``, its runtime library loaded from ``directory`` (compiled there once).

    Without a directory (nothing can be written) or with numba's allocation statistics on,
    numba initializes it itself.
    """
    system = nrt.rtsys
    if system._init:
        return
    if directory is None or not ENABLED or getattr(config, "NRT_STATS", False):
        system.initialize(context)
        return
    for name, address in _nrt_python.c_helpers.items():  # what numba registers first
        ll.add_symbol(name if name.startswith("_") else f"NRT_{name}", address)
    path = directory / RUNTIME_FILE
    kept = _read_runtime(path)
    if kept is None:
        library, object_code, bitcode = _compile_runtime(context)
        _write_runtime(path, object_code, bitcode)
    else:
        library = library_from_object(context.codegen(), ("nrt", "object", kept))
    system._library = library
    system._init = True
