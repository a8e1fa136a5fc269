"""The Python API (docs/python.md): cosmos.run, cosmos.load, cosmos.check and Run.

Data are compared with the log read independently (the ``mcap`` package's own
reader, JSON decoded here), names with the MuJoCo model, failures with what
``cosmos run`` prints for the same program.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest
from mcap.reader import make_reader

import cosmos
from cosmos.commands.run import run_program
from cosmos.run_result import PANDAS_MISSING
from cosmos.runtime.rates import Rates
from cosmos.workcell import SCENE_XML

pytest.importorskip("pandas")

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "python.md"

FAILING = """SPEED 0.2 m/s
PROC reach_up
  MOVE BY (0, 0, 5 mm)
  CONTACT UP FORCE 5 N \\
      SPEED 20 mm/s TIMEOUT 0.3 s   # nothing above the tool
END PROC
MOVE BY (0, 0, -5 mm)
reach_up
"""


def doc_blocks() -> list[str]:
    """The python blocks of docs/python.md, each padded with blank lines to its line in the file."""
    text = DOC.read_text(encoding="utf-8")
    blocks = re.finditer(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    return ["\n" * text.count("\n", 0, block.start(1)) + block.group(1) for block in blocks]


def messages(log: Path, topic: str) -> list[tuple[int, dict]]:
    """(log_time, decoded JSON) of every message on ``topic``, by the mcap package's reader."""
    with log.open("rb") as stream:
        out = []
        for _, channel, message in make_reader(stream).iter_messages(topics=[topic], log_time_order=True):
            assert channel.message_encoding == "json", (
                f"{topic} is {channel.message_encoding}: decode it here"
            )
            out.append((message.log_time, json.loads(message.data)))
    return out


def arm_joint_names() -> list[str]:
    model = mujoco.MjModel.from_xml_path(str(SCENE_XML))
    return [
        model.joint(i).name for i in range(model.njnt) if model.jnt_type[i] == mujoco.mjtJoint.mjJNT_HINGE
    ]


@pytest.fixture(scope="module")
def doc_run(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """The namespace after running every python block of docs/python.md, in a scratch directory."""
    where = tmp_path_factory.mktemp("doc")
    shutil.copytree(ROOT / "programs", where / "programs")
    namespace: dict = {"__name__": "docs_python"}
    previous = Path.cwd()
    os.chdir(where)
    try:
        for block in doc_blocks():
            exec(compile(block, str(DOC), "exec"), namespace)
    finally:
        os.chdir(previous)
    namespace["where"] = where
    return namespace


def test_import_cosmos_loads_no_heavy_module() -> None:
    """Catches an eager import in cosmos/__init__ (numpy, MuJoCo, pandas...) making `import cosmos` slow."""
    code = (
        "import sys, cosmos\n"
        "heavy = ('numpy', 'mujoco', 'pinocchio', 'numba', 'pandas', 'matplotlib', 'lark', 'click', 'mcap')\n"
        "print(','.join(m for m in heavy if m in sys.modules))\n"
        "assert callable(cosmos.run) and callable(cosmos.load) and callable(cosmos.check)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == ""


def test_doc_example_runs_and_its_states_match_the_logged_messages(doc_run: dict) -> None:
    """Catches a doc example that no longer runs, and a DataFrame column that is shifted, mislabelled,
    resorted or dropped relative to the /cosmos/state messages actually in the log."""
    run = doc_run["run"]
    log = doc_run["where"] / "logs" / "peg.mcap"
    assert run.log_path.resolve() == log.resolve() and run.log_path.is_absolute()
    assert (doc_run["where"] / "peg.png").stat().st_size > 10_000
    states = run.states
    logged = messages(log, "/cosmos/state")
    assert len(states) == len(logged) > 1000  # peg_in_hole.cos: 4.3 s at 250 Hz
    times = np.array([m["t"] for _, m in logged])
    np.testing.assert_array_equal(np.array([t for t, _ in logged]), np.round(times * 1e9))
    np.testing.assert_array_equal(states["t"], times)
    joints = arm_joint_names()
    assert len(joints) == 6 and list(states.columns[3:9]) == joints
    np.testing.assert_array_equal(states[joints].to_numpy(), [m["q"] for _, m in logged])
    np.testing.assert_array_equal(states[["x", "y", "z"]].to_numpy(), [m["x"] for _, m in logged])
    np.testing.assert_array_equal(states[["qw", "qx", "qy", "qz"]].to_numpy(), [m["quat"] for _, m in logged])
    wrench = ["fx", "fy", "fz", "mx", "my", "mz"]
    np.testing.assert_array_equal(states[wrench].to_numpy(), [m["wrench"] for _, m in logged])
    np.testing.assert_array_equal(states["line"], [m["line"] for _, m in logged])
    np.testing.assert_array_equal(states["segment"], [m["segment"] for _, m in logged])
    events = [(m["t"], m["kind"], m["line"], m["statement"]) for _, m in messages(log, "/cosmos/event")]
    assert [(e.t, e.kind, e.line, e.statement) for e in run.events] == events
    program = (ROOT / "programs" / "peg_in_hole.cos").read_text().splitlines()
    statements = [line for line in program if line[:1].isupper()]
    motions = [line for line in statements if not line.startswith("SPEED")]  # SPEED logs no "done"
    assert [e.kind for e in run.events].count("done") == len(motions)


def test_a_run_equals_its_log_loaded_and_differs_from_another_run(doc_run: dict) -> None:
    """Catches a Run holding something not read from its log (then run != load), and an __eq__
    that is always true."""
    run, touch = doc_run["run"], doc_run["touch"]
    loaded = cosmos.load(run.log_path)
    assert loaded.states.equals(run.states)
    assert loaded.events == run.events and loaded.outcome == run.outcome and loaded.ok
    assert touch != run and cosmos.load(touch.log_path) == touch


def test_failure_is_what_cosmos_run_prints(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Catches a failure rebuilt from the log with the wrong line or column (a statement inside a
    procedure, continued on the next line), reason or message, against the CLI's own error."""
    program = tmp_path / "reach.cos"
    program.write_text(FAILING)
    assert run_program(program, tmp_path / "cli.mcap", Rates(), 0) == 1
    printed = capsys.readouterr().err.strip()
    assert printed.startswith(f"{program}:4:3: CONTACT UP found no contact within 0.3 s")
    run = cosmos.run(program, log=tmp_path / "api.mcap")
    assert not run.ok and run.outcome is not None
    assert run.outcome.kind is cosmos.OutcomeKind.FAILED
    assert run.outcome.render() == printed
    assert run.outcome.location == f"{program}:4:3"
    assert run.events[-1].kind == "failed" and run.events[-1].line == 4


def test_ctrl_c_stops_the_arm_and_the_run_reports_it(tmp_path: Path) -> None:
    """Catches a SIGINT during cosmos.run that kills the process or is reported as success."""
    calls = []

    def interrupt(progress: object) -> None:
        calls.append(progress)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGINT)

    missed: list[int] = []  # the signal reached this handler instead of the run's: no KeyboardInterrupt
    previous = signal.signal(signal.SIGINT, lambda signum, frame: missed.append(signum))
    try:
        run = cosmos.run(
            "MOVE BY (0, 0, 50 mm)\nMOVE BY (0, 0, -50 mm)", log=tmp_path / "i.mcap", progress=interrupt
        )
    finally:
        signal.signal(signal.SIGINT, previous)
    assert not missed
    assert not run.ok and run.outcome is not None
    assert run.outcome.kind is cosmos.OutcomeKind.INTERRUPTED
    assert run.outcome.location == "<program>:1:1" and run.outcome.message == "MOVE BY interrupted"
    assert run.events[-1].kind == "interrupted" and run.events[-1].line == 1
    assert cosmos.load(run.log_path) == run


def test_a_log_cut_short_is_unfinished(tmp_path: Path) -> None:
    """Catches a cut log (a killed run) whose Run says ok because it holds no failure."""
    run = cosmos.run("MOVE BY (0, 0, 20 mm)\nWAIT 0.5 s", log=tmp_path / "whole.mcap")
    data = run.log_path.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    loaded = cosmos.load(cut)
    assert run.ok and not loaded.ok
    assert loaded.outcome is not None and loaded.outcome.kind is cosmos.OutcomeKind.UNFINISHED


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda d: cosmos.run(d / "missing.cos"), "missing.cos: No such file"),
        (lambda d: cosmos.run("programs/missing.cos"), "programs/missing.cos: No such file"),
        (lambda d: cosmos.run(d), "is a directory"),
        (lambda d: cosmos.run("MOVE BY (0, 0, 5 mm)\nCONTACT SIDEWAYS"), "<program>:2:9: CONTACT needs"),
        (lambda d: cosmos.run("MOVE BY (0, 0, 5 mm)", servo_hz=5000), "--servo-hz must be in"),
        (lambda d: cosmos.run("MOVE BY (0, 0, 5 mm)", seed="one"), "seed must be a whole number"),
        (lambda d: cosmos.run("MOVE BY (0, 0, 5 mm)", seed=-1), "from 0 up; got -1"),
        (lambda d: cosmos.run("MOVE BY (0, 0, 5 mm)", param_hz="fast"), "param_hz must be a number"),
        (lambda d: cosmos.run("MOVE BY (0, 0, 5 mm)", log=d), "is a directory; give a file name"),
        (lambda d: cosmos.check("MOVE TO nowhere", name="x.cos"), "x.cos:1:9: unknown name 'nowhere'"),
        (lambda d: cosmos.load(d / "none.mcap"), "none.mcap: no such file"),
        (lambda d: cosmos.load(SCENE_XML), "scene.xml: not an MCAP file"),
    ],
)
def test_user_errors_raise_cosmos_error_with_the_place(tmp_path: Path, call, message: str) -> None:
    """Catches a bad path, program, option or log escaping as a raw Python exception, or an error
    that does not name the file and place."""
    with pytest.raises(cosmos.CosmosError) as caught:
        call(tmp_path)
    assert message in str(caught.value)
    assert not list(tmp_path.glob("**/*.mcap")), "nothing may run before the error"


def test_check_returns_the_plan_and_errors_show_the_line() -> None:
    """Catches cosmos.check printing instead of returning, or an error without its source line."""
    plan = cosmos.check("MOVE BY (0, 0, 50 mm) SPEED 0.1 m/s\nWAIT 1 s")
    assert [step.kind.value for step in plan.steps] == ["move", "wait"]
    assert plan.steps[0].speed_limit_mps == pytest.approx(0.1)
    with pytest.raises(cosmos.ProgramError) as caught:
        cosmos.check("WAIT 1 s\nMOVE TO nowhere")
    assert str(caught.value).splitlines()[1:] == ["    MOVE TO nowhere", "            ^^^^^^^"]
    assert caught.value.span is not None and caught.value.span.line == 2


def test_states_without_pandas_says_how_to_install(doc_run: dict, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches a raw ImportError (or a traceback from inside) when the pandas extra is missing."""
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(cosmos.CosmosError) as caught:
        doc_run["run"].states  # noqa: B018
    assert str(caught.value) == PANDAS_MISSING
    assert "pip install 'cosmos-osc[pandas]'" in PANDAS_MISSING


def test_compile_warnings_are_python_warnings(tmp_path: Path) -> None:
    """Catches cosmos.run dropping the compiler's warnings (the CLI prints them on stderr)."""
    text = "PROC unused\n  WAIT 0.1 s\nEND PROC\nWAIT 0.02 s"
    assert [w.message for w in cosmos.check(text).warnings] == [
        "PROC unused is never called, so its statements were not checked"
    ]
    with pytest.warns(cosmos.CosmosWarning, match=r"<program>:1:6: warning: PROC unused is never called"):
        run = cosmos.run(text, log=tmp_path / "w.mcap")
    assert run.ok


def test_two_runs_in_one_second_keep_their_own_logs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Catches the API's default log path (logs/program-<UTC second>.mcap) taken again by a second
    run in the same second: the first run's log was overwritten, and its Run no longer equalled
    cosmos.load(run.log_path) (a loop of cosmos.run calls kept only the last log of each second)."""
    monkeypatch.chdir(tmp_path)
    first = cosmos.run("WAIT 10 ms\n")
    second = cosmos.run("WAIT 20 ms\n")
    assert first.log_path != second.log_path
    assert cosmos.load(first.log_path) == first and cosmos.load(second.log_path) == second


def test_runs_in_threads_at_once_load_the_kernels_once(tmp_path: Path) -> None:
    """Catches two ``cosmos.run`` calls in threads of a fresh process (a user's own sweep in a
    ThreadPoolExecutor) both loading a kernel at its first call: the second found numba's
    dispatcher closed by the first ("RuntimeError: compilation disabled"). Each threaded run must
    equal the same seed's run made alone."""
    script = f"""
import concurrent.futures, numpy, cosmos
source = "MOVE BY (0, 0, 20 mm)\\nCONTACT DOWN FORCE 5 N\\n"
def one(seed):
    return cosmos.run(source, seed=seed, log=r"{tmp_path}/t%d.mcap" % seed)
with concurrent.futures.ThreadPoolExecutor(2) as pool:
    runs = list(pool.map(one, [0, 1]))
alone = cosmos.run(source, seed=1, log=r"{tmp_path}/alone.mcap")
assert all(run.ok for run in runs), [run.outcome for run in runs]
assert numpy.array_equal(alone.record.state.x, runs[1].record.state.x)
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]


def test_a_log_never_replaces_its_program(tmp_path: Path) -> None:
    """Catches ``cosmos.run("peg.cos", log="peg.cos")`` writing the log over the program."""
    program = tmp_path / "peg.cos"
    program.write_text("WAIT 10 ms\n")
    with pytest.raises(cosmos.UsageError, match="is a file this command reads; give the log another name"):
        cosmos.run(program, log=program)
    assert program.read_text() == "WAIT 10 ms\n"
