"""A sweep's definition and its results file: JSON lines, appended run by run, resumable.

The first line is the sweep's header: the program's name and text digest, the seed, the
``--vary`` distributions (canonical SI text), the plant and the cosmos that made the runs (its
version and a digest of its package's files: runs of other controller code do not mix in).
Each following line is one run's result, written and flushed to the disk as the run ends, so a
sweep stopped by Ctrl-C or killed outright loses at most the runs then under way; run again
with the same arguments, it makes only the runs missing. A last line cut by a kill is dropped.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import IO, Any

from cosmos.errors import CosmosError, UsageError
from cosmos.realism.plant_realism import IDEAL, REALISTIC
from cosmos.sweep.parameters import Vary, draw, parse_varies
from cosmos.sweep.worker import RunTask

RESULTS_NAME = "results.jsonl"
"""The results file in a sweep's directory."""
FORMAT = "cosmos-sweep/1"


@functools.cache
def cosmos_code() -> str:
    """The running cosmos: its version and a digest of its package's files (code, grammar, models)."""
    import cosmos

    root = Path(cosmos.__file__).parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes())
    return f"{cosmos.__version__}+{digest.hexdigest()[:12]}"


class Keep(StrEnum):
    """Which runs' logs a sweep keeps (``--keep``)."""

    ALL = "all"
    FAILED = "failed"
    NONE = "none"


@dataclass(frozen=True)
class SweepSpec:
    """What a sweep runs: a program, a seed and distributions; the runs follow from them.

    Attributes:
        program: The program's name (its path as given).
        source: Its text.
        seed: The sweep's seed.
        varies: The ``--vary`` distributions.
        ideal: Every run on the ideal plant (``--ideal``) instead of the realistic one.
    """

    program: str
    source: str
    seed: int
    varies: tuple[Vary, ...]
    ideal: bool = False

    def header(self) -> dict[str, Any]:
        """The results file's first line."""
        return {
            "format": FORMAT,
            "program": self.program,
            "source_sha256": hashlib.sha256(self.source.encode()).hexdigest(),
            "seed": self.seed,
            "vary": [vary.text() for vary in self.varies],
            "plant": IDEAL if self.ideal else REALISTIC,
            "cosmos": cosmos_code(),
        }

    def task(self, index: int, keep: Keep = Keep.FAILED) -> RunTask:
        """Run ``index``: its values drawn from the seed and the index only."""
        return RunTask(
            index=index,
            program=self.program,
            source=self.source,
            values=draw(self.varies, self.seed, index),
            keep_log=keep == Keep.ALL,
            keep_failed_log=keep == Keep.FAILED,
            ideal=self.ideal,
        )


def log_name(index: int) -> str:
    """The kept log of run ``index`` in the sweep's ``logs/`` folder."""
    return f"run-{index:05d}.mcap"


def read_results(path: Path) -> tuple[dict[str, Any], dict[int, dict[str, Any]], int]:
    """A results file's header, its runs by index, and the byte length of its complete lines.

    Raises:
        CosmosError: The file cannot be read or its header is not a sweep's.
    """
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise UsageError(f"{path}: no such file") from None
    except OSError as error:
        raise CosmosError(f"{path}: cannot read: {error.strerror}") from None
    complete = data.rfind(b"\n") + 1  # a line without its newline was cut by a kill
    lines = data[:complete].splitlines()
    try:
        header = json.loads(lines[0]) if lines else None
    except ValueError:
        header = None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise CosmosError(f"{path}: not a cosmos sweep's results file (no '{FORMAT}' header line)")
    runs: dict[int, dict[str, Any]] = {}
    for number, line in enumerate(lines[1:], start=2):
        try:
            result = json.loads(line)
            runs[int(result["index"])] = result
        except (ValueError, KeyError, TypeError):
            raise CosmosError(f"{path}:{number}: not a run's result") from None
    return header, runs, complete


class ResultsFile:
    """The results file of one sweep, opened to add runs; the runs already there by index.

    Raises:
        UsageError: The file holds another sweep (another program text, seed or distributions).
    """

    def __init__(self, path: Path, spec: SweepSpec) -> None:
        self.path = path
        header = spec.header()
        self.done: dict[int, dict[str, Any]] = {}
        complete: int | None = None  # the length of the runs kept, when the file is there
        if path.exists():
            found, self.done, complete = read_results(path)
            if found.get("cosmos") != header["cosmos"] and {**found, "cosmos": header["cosmos"]} == header:
                raise UsageError(
                    f"{path}: its runs were made by another cosmos ({found.get('cosmos', 'before 0.1.0+')}, "
                    f"this is {header['cosmos']}) and would not mix with this one's; give another --out or "
                    "delete it"
                )
            if {k: found.get(k) for k in header} != header:
                raise UsageError(
                    f"{path}: holds another sweep (program text, seed, --vary or --ideal differ); "
                    "give another --out or delete it"
                )
        try:
            if complete is not None:
                with path.open("r+b") as stream:
                    stream.truncate(complete)
            else:
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(json.dumps(header) + "\n", encoding="utf-8")
            self._stream: IO[str] = path.open("a", encoding="utf-8")
        except OSError as error:
            raise UsageError(f"{path}: cannot write the sweep's results: {error.strerror or error}") from None

    def add(self, result: dict[str, Any]) -> None:
        """Append one run's result and put it on the disk before going on."""
        self._stream.write(json.dumps(result) + "\n")
        self._stream.flush()
        os.fsync(self._stream.fileno())
        self.done[int(result["index"])] = result

    def close(self) -> None:
        """Close the file."""
        self._stream.close()


def sample(path: Path, index: int) -> tuple[dict[str, Any], dict[str, float]]:
    """``--sample FILE:N``: the header of a sweep's results file and run ``N``'s values, redrawn.

    Raises:
        UsageError: Not a results file, or ``N`` out of range.
        CosmosError: The values redrawn differ from the ones the file recorded for run ``N``.
    """
    header, runs, _ = read_results(path)
    if index < 0:
        raise UsageError(f"--sample {path}:{index}: a run index is >= 0")
    varies = parse_varies(header.get("vary", []))
    values = draw(varies, int(header["seed"]), index)
    recorded = runs.get(index, {}).get("values")
    if recorded is not None and recorded != values:
        raise CosmosError(f"{path}: run {index}'s recorded values differ from its redrawn ones")
    return header, values


def parse_sample(text: str) -> tuple[Path, int]:
    """``FILE:N`` of ``--sample``."""
    file, sep, index = text.rpartition(":")
    if not sep or not index.strip().isdigit():
        raise UsageError(f"--sample {text}: expected FILE:N, a sweep's results file and a run index")
    return Path(file), int(index)


def results_list(runs: dict[int, dict[str, Any]], count: int) -> Sequence[dict[str, Any]]:
    """The results of runs ``0 .. count-1`` that are done, in index order."""
    return [runs[i] for i in range(count) if i in runs]
