"""``cosmos run`` and Python's garbage collector: off while it starts up, on while the arm runs."""

from __future__ import annotations

import gc
from pathlib import Path

import pytest
from click.testing import CliRunner

import cosmos.commands.run as run_command
from cosmos.cli import cli


def test_run_starts_up_without_the_collector_and_runs_with_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches ``cosmos run`` walking start-up's objects (modules, models, kernels) with the
    collector again and again (250 collections, 0.13 s of a 1.3 s run), and a run whose loop
    goes on without a collector (cyclic garbage growing through a long run), or that leaves it
    off for the caller."""
    program = tmp_path / "wait.cos"
    program.write_text("WAIT 10 ms\n")
    seen: list[tuple[bool, int]] = []
    collect = run_command.collect_from_here

    def watched() -> None:
        seen.append((gc.isenabled(), gc.get_freeze_count()))
        collect()
        seen.append((gc.isenabled(), gc.get_freeze_count()))

    monkeypatch.setattr(run_command, "collect_from_here", watched)
    try:
        result = CliRunner().invoke(cli, ["run", str(program), "--log", str(tmp_path / "wait.mcap")])
    finally:
        gc.unfreeze()  # this test process's objects are collectable again
    assert result.exit_code == 0, result.output
    (off, frozen_before), (on, frozen_after) = seen
    assert not off and on
    assert frozen_after > frozen_before  # start-up's objects are skipped from then on
    assert gc.isenabled()


def test_a_caller_with_its_collector_on_keeps_it() -> None:
    """Catches an in-process run (a test, the REPL) having its objects frozen for ever."""
    assert gc.isenabled()
    before = gc.get_freeze_count()
    run_command.collect_from_here()
    assert gc.isenabled() and gc.get_freeze_count() == before
