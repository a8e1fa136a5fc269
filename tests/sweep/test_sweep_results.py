"""The results file: a header that fixes the sweep, lines added one by one, a cut last line dropped."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import cosmos
from cosmos.errors import UsageError
from cosmos.sweep.parameters import parse_varies
from cosmos.sweep.results import ResultsFile, SweepSpec, read_results, sample

SOURCE = "MOVE BY (0, 0, 10 mm)\n"


def spec(seed: int = 1, source: str = SOURCE) -> SweepSpec:
    return SweepSpec("p.cos", source, seed, parse_varies(["hole.x=normal(0,1mm)"]))


def fake_result(index: int, values: dict) -> dict:
    return {"index": index, "ok": True, "values": values}


def test_resuming_keeps_the_runs_and_drops_a_line_cut_by_a_kill(tmp_path: Path) -> None:
    """Catches a cut last line breaking the resumed sweep, or being kept and then appended to."""
    path = tmp_path / "results.jsonl"
    results = ResultsFile(path, spec())
    for index in (0, 2):
        results.add(fake_result(index, spec().task(index).values))
    results.close()
    with path.open("a") as stream:
        stream.write('{"index": 1, "ok": tr')  # a kill in the middle of a write
    again = ResultsFile(path, spec())
    assert sorted(again.done) == [0, 2]
    again.add(fake_result(1, spec().task(1).values))
    again.close()
    header, runs, _ = read_results(path)
    assert header == spec().header() and sorted(runs) == [0, 1, 2]
    assert all(json.loads(line) for line in path.read_text().splitlines())


@pytest.mark.parametrize("other", [spec(seed=2), spec(source=SOURCE + "MOVE BY (0, 0, -10 mm)\n")])
def test_another_sweep_in_the_same_folder_is_refused(tmp_path: Path, other: SweepSpec) -> None:
    """Catches results of two different sweeps mixed in one file (another seed or program text)."""
    path = tmp_path / "results.jsonl"
    ResultsFile(path, spec()).close()
    with pytest.raises(UsageError, match="holds another sweep"):
        ResultsFile(path, other)


def test_an_out_folder_that_cannot_be_made_is_one_line(tmp_path: Path) -> None:
    """Catches `cosmos sweep ... --out /proc/x` ending in pathlib's FileNotFoundError traceback."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(UsageError, match=r"file/sweep/results.jsonl: cannot write the sweep.s results"):
        ResultsFile(blocker / "sweep" / "results.jsonl", spec())


def test_sample_redraws_a_run_s_values_from_the_header(tmp_path: Path) -> None:
    """Catches --sample reading values that the header's seed and distributions do not give."""
    path = tmp_path / "results.jsonl"
    results = ResultsFile(path, spec())
    results.add(fake_result(4, spec().task(4).values))
    results.close()
    assert sample(path, 4)[1] == spec().task(4).values
    assert sample(path, 9)[1] == spec().task(9).values  # not run yet: drawn all the same
    lines = path.read_text().splitlines()
    lines[1] = json.dumps(fake_result(4, {"hole.x": 1.0, "seed": 0.0}))
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(Exception, match="recorded values differ"):
        sample(path, 4)


def test_runs_of_other_cosmos_code_are_not_resumed(tmp_path: Path) -> None:
    """A results file whose runs another cosmos made (another version, or its controller code
    edited) is refused, saying so. Catches a sweep that silently resumed from runs of the code
    before an edit, mixing two controllers' outcomes in one success rate."""
    path = tmp_path / "results.jsonl"
    results = ResultsFile(path, spec())
    results.add(fake_result(0, spec().task(0).values))
    results.close()
    lines = path.read_text().splitlines()
    header = json.loads(lines[0])
    assert header["cosmos"].startswith(cosmos.__version__ + "+")
    header["cosmos"] = cosmos.__version__ + "+000000000000"
    path.write_text("\n".join([json.dumps(header), *lines[1:]]) + "\n")
    with pytest.raises(UsageError, match=r"made by another cosmos \(0\.1\.0\+000000000000"):
        ResultsFile(path, spec())
