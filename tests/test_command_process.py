"""The ``cosmos`` command's own process: one BLAS thread, MuJoCo without OpenGL, an exit without teardown.

Each test starts a script named ``cosmos`` (as the console script is) and reads what that
process did from the operating system (its threads) or from an exit handler of its own.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

COMMAND = """\
import atexit, dataclasses, json, os, sys
REPORT = {report!r}
GL = ("mujoco.egl", "mujoco.glfw", "mujoco.osmesa", "glfw")
GLANCED = ("scipy", "yaml", "numpy.ma", "importlib.metadata")

def report():
    with open(REPORT, "w") as out:
        json.dump({{
            "threads": len(os.listdir("/proc/self/task")),
            "gl": sorted(m for m in sys.modules if m in GL),
            "glanced": sorted(m for m in sys.modules if m in GLANCED),
            "MUJOCO_GL": os.environ.get("MUJOCO_GL"),
            "OPENBLAS_NUM_THREADS": os.environ.get("OPENBLAS_NUM_THREADS"),
            "dataclass_texts": len(getattr(vars(dataclasses).get("exec"), "used", ())),
        }}, out)

atexit.register(report)
from cosmos.cli import main
import numpy
if __name__ == "__main__":
    main()
"""


THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "GOTO_NUM_THREADS", "MKL_NUM_THREADS")
"""What OpenBLAS reads for its number of threads (a Dask cluster started in the tests sets them)."""


def _start(script: Path, *args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    environment = {key: value for key, value in os.environ.items() if key not in THREAD_VARIABLES}
    environment.update(env or {})
    return subprocess.run(
        [sys.executable, str(script), *args],
        capture_output=True,
        text=True,
        timeout=300,
        env=environment,
        cwd=script.parent,
    )


def _script(tmp_path: Path, name: str) -> tuple[Path, Path]:
    report = tmp_path / f"{name}.json"
    script = tmp_path / name
    script.write_text(COMMAND.format(report=str(report)), encoding="utf-8")
    return script, report


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="reads the process's threads from /proc")
def test_the_command_loads_numpy_with_one_blas_thread_and_leaves_the_variable_unset(tmp_path: Path) -> None:
    """Catches the command's numpy starting OpenBLAS's thread per core (40-50 ms of every start-up
    on two cores), the command's one thread leaking into the processes it starts (a sweep's
    workers would inherit it as if the user had set it), and the command compiling dataclasses'
    methods anew (:mod:`cosmos.commands.dataclass_code` not installed). The same script under
    another name (a program importing cosmos) keeps OpenBLAS's threads and Python's dataclasses:
    there, start-up is not the command's."""
    command, command_report = _script(tmp_path, "cosmos")
    other, other_report = _script(tmp_path, "other.py")
    assert _start(command, "--version").returncode == 0
    assert _start(other, "--version").returncode == 0
    ours, theirs = json.loads(command_report.read_text()), json.loads(other_report.read_text())
    assert ours["threads"] == 1
    assert ours["OPENBLAS_NUM_THREADS"] is None
    assert ours["dataclass_texts"] > 0 and theirs["dataclass_texts"] == 0
    if (os.cpu_count() or 1) > 1:
        assert theirs["threads"] > 1


def test_a_run_imports_mujoco_without_opengl_nor_what_numba_glances_at(tmp_path: Path) -> None:
    """Catches ``cosmos run`` importing MuJoCo's OpenGL backends (GLFW or EGL: 20-40 ms) though it
    never renders, ``MUJOCO_GL`` changed for the processes it starts, modules a run does not use
    imported for numba's glance at them (SciPy's version, PyYAML for a configuration file there is
    not, ``numpy.ma`` to see that an argument is not masked: 20-50 ms) or for numba's and MuJoCo's
    look for extensions and plugins no package declares (:mod:`importlib.metadata`: 10-30 ms), and
    the command's quick end
    losing what the interpreter's exit did: exit handlers (the first run's compile summary), the
    stdout written into a pipe, the exit status."""
    command, report = _script(tmp_path, "cosmos")
    program = tmp_path / "wait.cos"
    program.write_text("WAIT 10 ms\n", encoding="utf-8")
    log = tmp_path / "wait.mcap"
    done = _start(command, "run", str(program), "--log", str(log), env={"MUJOCO_GL": "egl"})
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == f"log: {log}"
    seen = json.loads(report.read_text())
    assert seen["gl"] == []
    assert seen["MUJOCO_GL"] == "egl"
    assert seen["glanced"] == []
    usage = _start(command, "run", str(tmp_path / "missing.cos"))
    assert usage.returncode == 2
    assert "missing.cos" in usage.stderr and "Traceback" not in usage.stderr


def test_numba_reads_its_configuration_file_in_a_run(tmp_path: Path) -> None:
    """Catches the run's import of numba without PyYAML (:func:`cosmos.commands.process.numba_alone`)
    hiding it where numba would read a ``.numba_config.yaml`` in the working directory: numba would
    then warn that it cannot read it, and ignore the user's settings."""
    pytest.importorskip("yaml")
    command, report = _script(tmp_path, "cosmos")
    (tmp_path / ".numba_config.yaml").write_text("# no settings\n", encoding="utf-8")
    program = tmp_path / "wait.cos"
    program.write_text("WAIT 10 ms\n", encoding="utf-8")
    done = _start(command, "run", str(program), "--log", str(tmp_path / "wait.mcap"))
    assert done.returncode == 0, done.stderr
    assert "YAML" not in done.stderr
    assert json.loads(report.read_text())["glanced"] == ["yaml"]
