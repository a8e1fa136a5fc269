"""Loading cached kernels (cosmos.jit.loading): what numba would have built, without its costs."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
from pathlib import Path

import llvmlite.binding as ll
import pytest

from cosmos.jit import loading

ROOT = Path(__file__).resolve().parents[1]

_KERNELS = """
import numpy as np
from cosmos.jit import kernel


@kernel
def callee(values):
    out = np.empty(values.shape[0])
    for i in range(values.shape[0]):
        out[i] = 2.0 * values[i] + 1.0
    return out


@kernel
def caller(values):
    return callee(values).sum()
"""

_RUN = """
import json, sys
from numba.core import event
import numpy as np
import jitprobe

compiled = []


class Listener(event.Listener):
    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        if function.__module__ == "jitprobe":  # not numba's own implementations
            compiled.append(function.__name__)

    def on_end(self, ev):
        pass


event.register("numba:compile", Listener())
values = np.arange(4.0)
report = {"callee": jitprobe.callee(values).tolist()}
report["arrayobj_after_callee"] = "numba.np.arrayobj" in sys.modules
from numba.core.runtime import nrt
report["runtime_loaded"] = "_get_module_for_linking" in vars(nrt.rtsys.library)  # not compiled here
if sys.argv[1] == "both":
    report["caller"] = float(jitprobe.caller(values))
report["compiled"] = compiled
print(json.dumps(report))
"""


def _run(tmp_path: Path, what: str) -> dict[str, object]:
    env = {k: v for k, v in os.environ.items() if k != "XDG_CACHE_HOME"}
    env.update(COSMOS_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=f"{tmp_path}{os.pathsep}{ROOT}")
    done = subprocess.run(
        [sys.executable, "-c", _RUN, what], capture_output=True, text=True, env=env, timeout=600, check=False
    )
    assert done.returncode == 0, done.stderr[-3000:]
    report: dict[str, object] = json.loads(done.stdout.strip().splitlines()[-1])
    return report


@pytest.mark.skipif(
    not loading.ENABLED, reason="another numba loads its kernels itself (cosmos.jit.loading.CHECKED_NUMBA)"
)
def test_a_cached_kernel_loads_without_its_bitcode_and_still_links_into_a_new_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches the three savings of loading breaking a kernel: the loaded kernel must compute what
    it computed when compiled, numba's ``arrayobj`` (whose environment it references) must stay
    unimported, a kernel compiled later must still inline it (its bitcode, now parsed only when
    linked: a wrong lazy parse fails to link or crashes), and the symbols read from the object's
    ELF table must be exactly those numba finds walking the bitcode (a missing entry point makes
    numba call address 0: a segmentation fault, as a misread ELF header did). numba's runtime,
    compiled in every process before, must be compiled once, then loaded and still link."""
    (tmp_path / "jitprobe.py").write_text(_KERNELS)
    first = _run(tmp_path, "callee")  # compiles the callee into the fresh cache
    assert first["callee"] == [1.0, 3.0, 5.0, 7.0] and first["compiled"] == ["callee"]
    assert first["runtime_loaded"] is False  # compiled, and kept beside the kernels
    assert len(list((tmp_path / "cache").rglob(loading.RUNTIME_FILE))) == 1
    second = _run(tmp_path, "both")  # loads the callee; compiles the caller against it
    assert second["callee"] == [1.0, 3.0, 5.0, 7.0]
    assert second["compiled"] == ["caller"], second["compiled"]
    assert second["caller"] == 16.0
    assert second["arrayobj_after_callee"] is False
    assert second["runtime_loaded"] is True  # numba's runtime from the cache, linked into the caller

    monkeypatch.syspath_prepend(str(tmp_path))
    data_files = sorted((tmp_path / "cache").rglob("*.nbc"))
    assert len(data_files) == 2
    for path in data_files:
        payload = loading._KernelUnpickler(io.BytesIO(path.read_bytes())).load()
        _, kind, (object_code, bitcode) = payload[0]
        assert kind == "object"
        module = ll.parse_bitcode(bitcode)
        walked = {
            symbol.name
            for symbols in (module.functions, module.global_variables)
            for symbol in symbols
            if not symbol.is_declaration
        }
        assert loading.object_symbols(object_code) == walked, path.name


def test_an_object_that_is_not_elf_is_left_to_numba() -> None:
    """Catches a Mach-O or COFF object (macOS, Windows) read as ELF: its symbols must come from
    numba's own walk of the bitcode (None here), not from garbage."""
    assert loading.object_symbols(b"\xcf\xfa\xed\xfe" + bytes(200)) is None
    assert loading.object_symbols(b"\x7fELF\x01\x01" + bytes(200)) is None  # 32-bit
    assert loading.object_symbols(b"") is None


def test_array_arguments_are_typed_as_numba_types_them() -> None:
    """Catches cosmos's typing of a kernel's array argument (which skips importing ``numpy.ma``,
    cosmos.jit.argument_types) differing from numba's own: a wrong layout, dtype, dimension
    count or read-only flag would call the kernel's code on memory it was not compiled for;
    and a masked array must still be refused, as numba refuses it."""
    import numpy as np
    from numba.core import errors
    from numba.core.typing.typeof import Purpose, typeof, typeof_impl

    from cosmos.jit import argument_types

    assert loading.ENABLED
    assert typeof_impl.dispatch(np.ndarray) is argument_types.array_type
    base = np.arange(24.0).reshape(2, 3, 4)
    frozen = np.ones((3, 3))
    frozen.setflags(write=False)
    arrays = [
        base,
        np.asfortranarray(base),
        base[:, ::2],
        base[0, 1],
        np.zeros(0),
        np.array(3.0),
        np.arange(6, dtype=np.int32),
        np.zeros(4, dtype=np.complex128),
        np.zeros(3, dtype=bool),
        frozen,
        frozen.T,
    ]
    for array in arrays:
        ours = typeof(array, Purpose.argument)
        assert ours == argument_types.NUMBA_ARRAY_TYPE(array, None), array
        assert (ours.layout, ours.ndim, ours.mutable) == (
            "C" if array.flags.c_contiguous else "F" if array.flags.f_contiguous else "A",
            array.ndim,
            array.flags.writeable,
        )
    import numpy.ma

    with pytest.raises(errors.NumbaTypeError, match="MaskedArray"):
        typeof(numpy.ma.masked_array([1.0, 2.0], mask=[False, True]), Purpose.argument)
