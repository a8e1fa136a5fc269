"""cosmos bench: the figures issues 3 and 20 ask for, and a floor that moves as the workload does."""

import json
from pathlib import Path

import numpy as np
import pytest

from cosmos.bench import programs, suite
from cosmos.bench.language import check_end_to_end_s
from cosmos.bench.obstacles import bench_obstacles
from cosmos.bench.programs import executor_run
from cosmos.bench.servo import _floor_tick_us, _workload_setpoint, _workload_torques, measure
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.runtime.loop import Runtime
from cosmos.runtime.rates import Rates


def test_floor_replays_the_workload_motion():
    """Open loop, the workload's torques give the workload's trajectory (MuJoCo is deterministic):
    the floor times the same physics, not an arm fallen onto the table."""
    robot = build_robot_model()
    torques = _workload_torques(robot, 400)
    controlled = Runtime(Plant(), robot, Rates())
    controlled.set_setpoint(_workload_setpoint(controlled))
    for _ in range(400):
        controlled.tick()
    replay = Plant()
    assert _floor_tick_us(replay, robot, torques, 100) > 0.0
    np.testing.assert_array_equal(replay.data.qpos, controlled.plant.data.qpos)
    assert replay.data.ncon == 0


def test_measure_reports_the_phases_and_the_floor():
    figures = measure(ticks=300, repeats=2)
    assert len(figures["tick_us_runs"]) == len(figures["floor_tick_us_runs"]) == 2
    assert figures["tick_us"] == min(figures["tick_us_runs"])
    assert figures["floor_tick_us"] == min(figures["floor_tick_us_runs"])
    assert set(figures["phases_us"]) == {"sense", "parameters", "servo", "physics", "record"}
    assert all(cost > 0.0 for cost in figures["phases_us"].values())
    assert figures["timed_tick_us"] >= sum(figures["phases_us"].values())
    assert figures["ticks_per_second"] == 1e6 / figures["tick_us"]
    assert figures["ratio_to_floor"] == figures["tick_us"] / figures["floor_tick_us"]


def test_executor_run_counts_the_servo_ticks_of_the_program(tmp_path: Path) -> None:
    """The executor's per-tick cost divides by the ticks the program ran: a WAIT of 120 ms at 1 kHz is
    120 ticks (a count of plant steps, or of the session's hold, would make the figure wrong)."""
    program = tmp_path / "wait.cos"
    program.write_text("WAIT 120 ms\n")
    run = executor_run(program)
    assert run.ok
    assert abs(run.simulated_s - 0.120) < 2e-3
    assert abs(run.ticks - 120) <= 1
    assert run.tick_us == run.wall_s / run.ticks * 1e6
    assert run.real_time_factor == run.simulated_s / run.wall_s


def test_executor_share_is_measured_inside_the_same_run(tmp_path: Path) -> None:
    """Catches the executor's own share measured against a tick that never ran in it (runtime time 0,
    or more than the loop's whole time): the runtime's ticks are timed inside the executor's loop."""
    program = tmp_path / "move.cos"
    program.write_text("MOVE BY (0, 0, 10 mm) SPEED 0.1 m/s\n")
    run = executor_run(program)
    assert run.ok
    assert 0.0 < run.runtime_s < run.wall_s
    assert run.to_runtime_tick_alone == run.wall_s / run.runtime_s > 1.0
    assert run.runtime_tick_us == run.runtime_s / run.ticks * 1e6


def test_runtime_setup_of_each_segment_is_the_runtimes(tmp_path: Path) -> None:
    """Catches the runtime's set-up of a segment (its fresh evaluation, its servo's setpoint and rotation
    plan) charged to the executor: timed inside the same run, beside the ticks, and counted with them."""
    program = tmp_path / "moves.cos"
    program.write_text("MOVE BY (0, 0, 10 mm) SPEED 0.1 m/s\nMOVE BY (10 mm, 0, 0) SPEED 0.1 m/s\n")
    run = executor_run(program)
    assert run.ok
    assert 0.0 < run.setup_s < run.wall_s - run.runtime_s  # two segments' set-up, within the executor's loop
    assert run.to_runtime_tick == run.wall_s / (run.runtime_s + run.setup_s) > 1.0
    assert run.to_runtime_tick < run.to_runtime_tick_alone


def test_obstacle_bench_compares_against_a_bare_tick() -> None:
    """The ratios are to the bare controller (no slots, no field), and the ten obstacles really act on
    the arm (some within the influence distance) while none is near with no obstacle."""
    figures = bench_obstacles(ticks=400, counts=(0, 10))
    for count in (0, 10):
        assert figures[f"ratio_{count}"] == figures[f"tick_us_{count}"] / figures["tick_us_bare"]
    assert figures["in_influence_0"] == 0.0
    assert figures["in_influence_10"] > 0.0
    assert figures["field_us_per_tick_10"] > figures["field_us_per_tick_0"]
    for key in ("bare", "0", "10"):  # MuJoCo's steps are timed inside each tick, a part of it
        assert 0.0 < figures[f"physics_us_per_tick_{key}"] < figures[f"tick_us_{key}"]


def test_check_end_to_end_runs_the_command_on_a_generated_program() -> None:
    """``cosmos check`` is timed as a whole process that succeeds (a failing check must not be timed)."""
    runs = check_end_to_end_s(60, repeats=1)
    assert len(runs) == 1 and runs[0] > 0.0


def test_whole_run_timings_repeat_into_the_same_log_directory(tmp_path: Path) -> None:
    """Catches the bench's repeated `cosmos run` failing on its own previous log ("already exists"):
    best-of-N timings write the same log path again, so they must say --force."""
    from cosmos.bench.programs import startup_s

    assert startup_s(tmp_path) > 0.0
    assert startup_s(tmp_path) > 0.0


def test_whole_runs_are_timed_as_a_user_starts_them(tmp_path: Path) -> None:
    """Catches the start-up figure measuring a run no user has: ``python -m cosmos`` instead of
    the installed command, and every module's bytecode compiled again in every process where the
    machine sets PYTHONDONTWRITEBYTECODE (0.15 s of 1.3). The CPU seconds are the child's own."""
    import sys

    from cosmos.bench.programs import command, startup_run, user_environment

    script = Path(sys.executable).with_name("cosmos")
    if script.is_file():  # an install (this venv): its command, not `python -m cosmos`
        assert command() == [str(script)]
    assert "PYTHONDONTWRITEBYTECODE" not in user_environment({"PYTHONDONTWRITEBYTECODE": "1", "A": "b"})
    run = startup_run(tmp_path)
    assert run.cpu_s > 0.2 and run.wall_s > 0.0  # numpy, MuJoCo and numba alone take more


def test_a_program_that_fails_is_timed_and_a_broken_run_is_one_clear_error(tmp_path: Path) -> None:
    """A shipped program that fails still runs whole: its run is timed (its failure is the
    executor run's ``ok``). A run that ends otherwise (a usage error, a crash) is a CosmosError the
    command prints on one line. Catches the RuntimeError traceback `cosmos bench` died with
    while peg_in_hole.cos failed its INSERT."""
    from cosmos.bench.programs import program_run
    from cosmos.errors import CosmosError

    failing = tmp_path / "fails.cos"
    failing.write_text("MOVE TO table + (0, 0, 20 mm)\nMOVE BY (0, 0, -40 mm)\n", encoding="utf-8")
    assert program_run(failing, tmp_path).wall_s > 0.0
    with pytest.raises(CosmosError, match=r"exited with status 2: .*missing.cos"):
        program_run(tmp_path / "missing.cos", tmp_path)


def test_the_clock_around_each_tick_is_left_out_of_the_executor_share(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Catches the bench charging the executor with its own clock around each tick (two clock reads
    and a call, 0.1-0.4 us a tick: 1-2 % of a tick, which ``cosmos run`` never pays). With a clock
    that moves 100 ns at each read and calls that cost nothing, the wrapper adds 200 ns a tick to the
    loop, 100 of them between its reads (inside the time counted as the runtime's)."""
    now = [0]

    def clock() -> int:
        now[0] += 100
        return now[0]

    monkeypatch.setattr(programs.time, "perf_counter_ns", clock)
    extra, clocks = programs.tick_clock_cost_ns(calls=1000, looks=2)
    assert extra == pytest.approx(200.0, abs=0.5)
    assert clocks == pytest.approx(100.0, abs=0.5)


def test_an_install_without_shipped_programs_reports_nothing_measured(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """From a wheel (``pip install .``: no ``programs/``) ``cosmos bench`` printed ``executor ...:
    0.0 us/tick`` and ``"executor_tick_us": 0.0`` as if measured: the figures must be null and the
    report must say where the programs are and why there are none."""
    monkeypatch.setattr(suite, "shipped_programs", list)
    figures = suite.programs_figures()
    assert figures["programs"] == {} and figures["executor_tick_us"] is None
    assert figures["executor_to_runtime_tick"] is None and figures["startup_s"] > 0  # type: ignore[operator]
    monkeypatch.setattr(suite, "measure", lambda: {"tick_us": 15.0, "floor_tick_us": 10.0})
    monkeypatch.setattr(suite, "programs_figures", lambda: figures)
    monkeypatch.setattr(suite, "bench_obstacles", dict)
    monkeypatch.setattr(suite, "bench_compile", lambda lines: 0.1)
    monkeypatch.setattr(suite, "check_end_to_end_s", lambda lines, repeats: [0.1])
    whole = suite.measure_all(first=False)
    assert whole["executor_to_bench_loop"] is None and whole["executor_to_floor"] is None
    json.dumps(whole, allow_nan=False)  # null, not 0.0 and not NaN
