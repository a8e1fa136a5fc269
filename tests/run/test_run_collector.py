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
    frozen = gc.get_freeze_count()
    result = CliRunner().invoke(cli, ["run", str(program), "--log", str(tmp_path / "wait.mcap")])
    assert result.exit_code == 0, result.output
    (off, frozen_before), (on, frozen_after) = seen
    assert not off and on
    assert frozen_after > frozen_before  # start-up's objects are skipped from then on
    assert gc.isenabled() and gc.get_freeze_count() == frozen  # an in-process caller's are its own again


def test_check_runs_without_the_collector_and_a_whole_process_keeps_its_objects_frozen(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches ``cosmos check`` collecting through its start-up (115 collections, 25 ms of 0.35 s),
    and the collector left off after it, or, in the command's own process, everything start-up
    made walked again by the first collection after it (the whole heap in the youngest generation)."""
    import cosmos.cli as cli_module
    import cosmos.commands.check as check_command

    program = tmp_path / "move.cos"
    program.write_text("MOVE BY (0, 0, 10 mm)\n")
    seen: list[bool] = []
    check = check_command.check_program

    def watched(*args: object, **kwargs: object) -> int:
        seen.append(gc.isenabled())
        return check(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(check_command, "check_program", watched)
    frozen = gc.get_freeze_count()
    assert CliRunner().invoke(cli, ["check", str(program)]).exit_code == 0
    assert seen == [False] and gc.isenabled() and gc.get_freeze_count() == frozen
    monkeypatch.setattr(cli_module, "_WHOLE_PROCESS", [True])
    try:
        assert CliRunner().invoke(cli, ["check", str(program)]).exit_code == 0
        assert gc.isenabled() and gc.get_freeze_count() > frozen
    finally:
        gc.unfreeze()


def test_a_caller_with_its_collector_on_keeps_it() -> None:
    """Catches an in-process run (a test, the REPL) having its objects frozen for ever."""
    assert gc.isenabled()
    before = gc.get_freeze_count()
    run_command.collect_from_here()
    assert gc.isenabled() and gc.get_freeze_count() == before


def test_main_called_in_process_leaves_the_callers_objects_collectable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches a test (or any caller) that runs ``cosmos.cli.main()`` in its own process being
    taken for the command's own process: start-up's objects, its own included, stayed frozen,
    uncollectable for the rest of the process (the suite failed on the freeze count)."""
    import sys

    from cosmos.cli import main

    program = tmp_path / "wait.cos"
    program.write_text("WAIT 10 ms\n")
    frozen = gc.get_freeze_count()
    monkeypatch.setattr(sys, "argv", ["cosmos", "run", str(program), "--log", str(tmp_path / "w.mcap")])
    with pytest.raises(SystemExit) as done:
        main()
    assert done.value.code == 0
    assert gc.isenabled() and gc.get_freeze_count() == frozen
