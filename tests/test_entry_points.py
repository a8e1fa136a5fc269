"""numba's extensions and MuJoCo's plugins: found without :mod:`importlib.metadata`, loaded when declared."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from cosmos.commands import entry_points

COMMAND = """\
from cosmos.cli import main
if __name__ == "__main__":
    main()
"""

DECLARED = """\
[mujoco.plugins]
marker = cosmos_test_marker:plugin

[numba_extensions]
init = cosmos_test_marker:extension
"""

MARKER = """\
import os
def _mark(what):
    with open(os.environ["COSMOS_TEST_MARKS"], "a") as marks:
        marks.write(what + "\\n")
def plugin():
    _mark("mujoco plugin")
def extension():
    _mark("numba extension")
"""


def _package(directory: Path, entry_points_text: str) -> None:
    info = directory / "cosmos_test_marker-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: cosmos-test-marker\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(entry_points_text)
    (directory / "cosmos_test_marker.py").write_text(MARKER)


def test_declared_groups_are_read_as_importlib_metadata_finds_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches the scan missing a package that declares numba's or MuJoCo's group (its extension
    would not be loaded), or answering for a path it cannot read (a zip)."""
    import importlib.machinery

    standard = [finder for finder in sys.meta_path if not hasattr(finder, "find_distributions")]
    monkeypatch.setattr(sys, "meta_path", [*standard, importlib.machinery.PathFinder])
    bare = tmp_path / "bare"
    bare.mkdir()
    monkeypatch.setattr(sys, "path", [str(bare)])
    assert entry_points.declared_groups() == set()
    _package(tmp_path / "declared", DECLARED)
    monkeypatch.setattr(sys, "path", [str(bare), str(tmp_path / "declared")])
    assert entry_points.declared_groups() == {"numba_extensions", "mujoco.plugins"}
    asked = (  # importlib.metadata itself, in a clean interpreter (another test's finders aside)
        "import importlib.metadata as m, sys; "
        f"sys.path[:] = [{str(bare)!r}, {str(tmp_path / 'declared')!r}]; "
        "print(sorted(g for g in sys.argv[1:] if any(p.module == 'cosmos_test_marker' "
        "for p in m.entry_points(group=g))))"
    )
    found = subprocess.run(
        [sys.executable, "-c", asked, *entry_points.GROUPS], capture_output=True, text=True, check=True
    )
    assert found.stdout.strip() == str(sorted(entry_points.GROUPS))
    archive = tmp_path / "packages.zip"
    with zipfile.ZipFile(archive, "w") as packed:
        packed.writestr("x.py", "")
    monkeypatch.setattr(sys, "path", [str(bare), str(archive)])
    assert entry_points.declared_groups() is None

    class OwnPackages:  # a finder that finds packages of its own (importlib.metadata asks it too)
        def find_distributions(self, *args: object) -> list[object]:
            return []

    monkeypatch.setattr(sys, "path", [str(bare)])
    monkeypatch.setattr(sys, "meta_path", [*sys.meta_path, OwnPackages()])
    assert entry_points.declared_groups() is None


def _run(tmp_path: Path) -> tuple[subprocess.CompletedProcess[str], Path]:
    command = tmp_path / "cosmos"
    command.write_text(COMMAND)
    program = tmp_path / "wait.cos"
    program.write_text("WAIT 10 ms\n")
    marks = tmp_path / "marks.txt"
    env = dict(os.environ, COSMOS_TEST_MARKS=str(marks), MUJOCO_GL="egl")
    done = subprocess.run(
        [sys.executable, str(command), "run", str(program), "--log", str(tmp_path / "wait.mcap")],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
        cwd=tmp_path,
    )
    return done, marks


def test_a_declared_extension_and_plugin_are_loaded_by_a_run(tmp_path: Path) -> None:
    """Catches the run answering "no extension, no plugin" though a package declares them (numba and
    MuJoCo would not load what the user installed)."""
    _package(tmp_path, DECLARED)  # beside the script: on its sys.path
    done, marks = _run(tmp_path)
    assert done.returncode == 0, done.stderr
    assert sorted(marks.read_text().splitlines()) == ["mujoco plugin", "numba extension"]


def test_the_stand_in_answers_other_questions_with_the_module() -> None:
    """Catches the stand-in hiding what :mod:`importlib.metadata` answers beyond the two groups (a
    library asking for its own entry points or its version while numba or MuJoCo is imported)."""
    import importlib.metadata

    stand_in = entry_points._Undeclared(frozenset(entry_points.GROUPS))
    assert stand_in.entry_points(group="mujoco.plugins") == ()
    scripts = importlib.metadata.entry_points(group="console_scripts")
    assert list(stand_in.entry_points(group="console_scripts")) == list(scripts)
    assert stand_in.version("numpy") == importlib.metadata.version("numpy")
