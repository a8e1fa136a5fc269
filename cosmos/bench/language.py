"""How long the language takes on long programs: compiling in process, ``cosmos check`` end to end.

The programs are generated (:func:`bench_program`): every kind of motion
statement, the numbers varied so that no two blocks are alike. ``cosmos check``
is timed from process start to exit, printing included, as a user sees it.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from cosmos.lang import compile_program
from cosmos.rotations import FloatArray, readonly, rpy_to_matrix

_BLOCK = """\
MOVE TO hole + (0, 0, 80 mm) SPEED 0.2 m/s
CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s
SLIDE +X BY 10 mm FORCE 6 N UNTIL FORCE X > 5 N OR DISTANCE > 9 mm
INSERT DOWN DEPTH 25 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s
WAIT 0.5 s
MOVE BY (0, 0, 100 mm)
COMPLY X Y STIFFNESS 200 N/m
MOVE TO (0.5, 0.1, 0.3) RPY (180 deg, 0, 0) VIA (0.45, 0, 0.4), (0.5, 0.05, 0.35) IN 2 s
COMPLY NONE
LET offset = (1 mm, 2 mm, 3 mm) * 2
"""


class _Fixture:
    """A fixture frame, z pointing down, like the workcell's."""

    def __init__(self, position: tuple[float, float, float]):
        self.position: FloatArray = readonly(position)
        self.rotation: FloatArray = rpy_to_matrix(math.pi, 0.0, 0.0)


_NUMBER = re.compile(r"\d+(\.\d+)?")


def _varied(block: str, index: int) -> str:
    """``block`` with three more decimals, ``index`` mod 1000, on every number but 0.

    So the blocks of a long program differ, as the lines of a generated one would
    (distinct coordinates, forces, times): no number is written twice in 1,000 blocks.
    """
    digits = f"{index % 1000:03d}"

    def longer(match: re.Match[str]) -> str:
        text = match.group(0)
        if text == "0":
            return text
        return text + digits if match.group(1) else f"{text}.{digits}"

    return _NUMBER.sub(longer, block)


def bench_program(lines: int = 10_000) -> str:
    """A program of about ``lines`` lines mixing every kind of motion statement, its numbers varied."""
    count = max(1, lines // len(_BLOCK.splitlines()))
    return "# benchmark program\n" + "".join(_varied(_BLOCK, index) for index in range(count))


def bench_compile(lines: int = 10_000) -> float:
    """Seconds to parse, check and compile a ``lines``-line program (one run).

    The grammar is loaded (and Lark's cache filled) before the clock starts; the
    clock stops when the plan is made, before it is freed.
    """
    source = bench_program(lines)
    fixtures = {"hole": _Fixture((0.55, 0.10, 0.02))}
    compile_program("WAIT 1 s", "<warm-up>", fixtures)
    start = time.perf_counter()
    compiled = compile_program(source, "<bench>", fixtures)
    elapsed = time.perf_counter() - start
    del compiled
    return elapsed


def check_end_to_end_s(lines: int, repeats: int = 3) -> list[float]:
    """Wall seconds of ``cosmos check`` on a generated ``lines``-line program, process start to exit.

    The plan is printed (to a pipe), as a user's terminal would receive it; each
    run is a new interpreter. One figure per run.
    """
    with tempfile.TemporaryDirectory(prefix="cosmos-bench-") as tmp:
        program = Path(tmp) / f"bench_{lines}.cos"
        program.write_text(bench_program(lines), encoding="utf-8")
        runs = []
        for _ in range(repeats):
            start = time.perf_counter()
            done = subprocess.run(
                [sys.executable, "-m", "cosmos", "check", str(program)], capture_output=True, check=False
            )
            runs.append(time.perf_counter() - start)
            if done.returncode != 0:
                raise RuntimeError(f"cosmos check failed on the bench program: {done.stderr.decode()[-500:]}")
    return runs
