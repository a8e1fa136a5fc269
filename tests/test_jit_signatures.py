"""What a run compiles: each kernel once, with one signature, and no linear-algebra import it does not use."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from cosmos.jit import loading

ROOT = Path(__file__).resolve().parents[1]

_RUN_AND_REPORT = """
import json, sys
UNUSED = ("scipy.linalg", "numba.np.arraymath", "numba.np.arrayobj", "numba.np.linalg")
from numba.core.dispatcher import Dispatcher
import cosmos
run = cosmos.run(sys.argv[1], log=sys.argv[2])
signatures = {}
for name, module in list(sys.modules.items()):
    if not name.startswith("cosmos"):
        continue
    for attribute, value in vars(module).items():
        if isinstance(value, Dispatcher) and value.py_func.__module__ == name:
            signatures[f"{name}.{attribute}"] = [str(s) for s in value.signatures]
print(json.dumps({
    "ok": run.ok,
    "signatures": signatures,
    "imported": sorted(m for m in UNUSED if m in sys.modules),
}))
"""


def test_a_run_compiles_each_kernel_once_and_skips_scipy_linalg(tmp_path: Path) -> None:
    """A first run compiled 148 functions for 46 kernels: the linear-algebra kernels in 11 variants
    for 4 functions (a transpose, a read-only row, a literal index each made another), the log
    writer's 11 for 8, the wrist wrench's kernel twice (read-only from the loop, writable from the
    servo), and ``np.outer`` in a kernel loaded SciPy's linear algebra (0.15 s) into every warm run.
    Catches a kernel the run calls from Python, or one with explicit signatures, holding a second
    signature, and a kernel that brings numba's ``arraymath`` (and with it ``scipy.linalg``) back,
    and loading a cached kernel that imports numba's implementation modules (``arrayobj``,
    ``linalg``: 0.1 s) to rebuild environments only object-mode code reads.
    (Kernels called only from other kernels are linked into them and never loaded on their own, so
    a warm run cannot see their variants: the linear ones have one explicit signature each.)
    The report is the second of two runs: on an empty kernel cache the first compiles, and numba's
    compiler imports ``arraymath`` itself (this test failed on a fresh machine's first suite)."""
    program = ROOT / "programs" / "peg_in_hole.cos"  # MOVE, CONTACT, INSERT: force and motion kernels
    env = dict(os.environ, MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
    for attempt in ("first", "warm"):  # compiling imports arraymath: the claim is about a warm run
        done = subprocess.run(
            [sys.executable, "-c", _RUN_AND_REPORT, str(program), str(tmp_path / f"{attempt}.mcap")],
            capture_output=True,
            text=True,
            env=env,
            timeout=600,
            check=False,
        )
    assert done.returncode == 0, done.stderr[-2000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["ok"]
    used = {name: sigs for name, sigs in report["signatures"].items() if sigs}
    assert len(used) >= 12, sorted(used)  # the run reached the controller's and the log's kernels
    several = {name: sigs for name, sigs in used.items() if len(sigs) > 1}
    assert several == {}, f"kernels compiled for more than one signature: {several}"
    imported = report["imported"]
    if not loading.ENABLED:  # another numba rebuilds environments itself, importing its own modules
        imported = [name for name in imported if name not in ("numba.np.arrayobj", "numba.np.linalg")]
    assert imported == [], f"a run imported {imported}"
