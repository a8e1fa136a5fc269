"""Runs on the realistic plant (the default) and the ideal one (``ideal=True``, ``--ideal``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import cosmos
from cosmos.errors import UsageError
from cosmos.realism import PlantRealism
from cosmos.replay.verify import verify_log
from cosmos.robots import PUMA560
from cosmos.runlog.reader import read_log
from cosmos.sweep.parameters import parse_varies
from cosmos.sweep.results import SweepSpec
from cosmos.sweep.variation import WorkcellVariation
from cosmos.sweep.worker import RunTask, run_task

PROGRAM = "MOVE BY (0, 0, 20 mm)\n"


def whole_counts(q: np.ndarray, resolution: np.ndarray) -> bool:
    """Every angle a whole count, to the log's 1e-6 rad (under 0.014 of a count)."""
    counts = q / resolution
    return bool(np.allclose(counts, np.round(counts), rtol=0, atol=0.5e-6 / resolution.min()))


def test_a_run_is_on_the_realistic_plant_unless_ideal_and_replay_verify_remakes_it(tmp_path: Path) -> None:
    """Catches the realistic plant not being the default, --ideal not reaching the plant, a plant
    not recorded in the log, and a realistic run that --verify cannot remake from its metadata."""
    realistic = cosmos.run(PROGRAM, log=tmp_path / "r.mcap", seed=4)
    ideal = cosmos.run(PROGRAM, log=tmp_path / "i.mcap", seed=4, ideal=True)
    assert realistic.ok and ideal.ok
    meta_r, meta_i = realistic.record.metadata, ideal.record.metadata
    assert (meta_r["plant"], meta_i["plant"]) == ("realistic", "ideal")
    assert float(meta_r["model_error"]) == 0.05 and "model_error" not in meta_i
    resolution = np.array(PlantRealism.drawn(4, PUMA560).encoder_resolution_rad)
    assert whole_counts(realistic.record.state.q, resolution)  # the controller saw encoder counts
    assert not whole_counts(ideal.record.state.q, resolution)  # and here MuJoCo's qpos
    verification = verify_log(read_log(tmp_path / "r.mcap"))
    assert verification.matches, verification


def test_ideal_must_be_a_bool() -> None:
    """Catches ideal="no" (truthy) silently running the ideal plant."""
    with pytest.raises(UsageError, match="ideal"):
        cosmos.run(PROGRAM, ideal="no")  # type: ignore[arg-type]


def test_sweep_model_error_and_ideal_reach_the_run_and_its_log(tmp_path: Path) -> None:
    """Catches --vary model_error not reaching the plant, a sweep's --ideal lost on the way to
    its workers, and a results header that would let an ideal sweep resume a realistic one."""
    (vary,) = parse_varies(["model_error=0.2"])
    task = RunTask(0, "p.cos", PROGRAM, {"model_error": vary.a, "seed": 3.0}, keep_log=True)
    result = run_task(task)
    log = tmp_path / "run.mcap"
    log.write_bytes(result["log_bytes"])
    metadata = read_log(log).metadata
    assert metadata["plant"] == "realistic" and float(metadata["model_error"]) == 0.2
    assert "--vary 'model_error=0.2'" in metadata["variation"]
    spec = SweepSpec("p.cos", PROGRAM, 0, (), ideal=True)
    assert spec.header()["plant"] == "ideal" and spec.task(0).ideal
    assert SweepSpec("p.cos", PROGRAM, 0, ()).header()["plant"] == "realistic"
    ideal_result = run_task(RunTask(0, "p.cos", PROGRAM, {"seed": 3.0}, keep_log=True, ideal=True))
    log.write_bytes(ideal_result["log_bytes"])
    assert read_log(log).metadata["plant"] == "ideal"
    assert WorkcellVariation(ideal=True).arguments().startswith("--ideal ")


def test_cosmos_run_ideal_flag_reaches_the_plant(tmp_path: Path) -> None:
    """Catches ``cosmos run --ideal`` parsed but not passed on (the run on the realistic plant)."""
    from click.testing import CliRunner

    from cosmos.cli import cli

    program = tmp_path / "p.cos"
    program.write_text(PROGRAM, encoding="utf-8")
    for flag, plant in (("--ideal", "ideal"), (None, "realistic")):
        log = tmp_path / f"{plant}.mcap"
        args = ["run", str(program), "--log", str(log), *([flag] if flag else [])]
        result = CliRunner().invoke(cli, args)
        assert result.exit_code == 0, result.output
        assert read_log(log).metadata["plant"] == plant
