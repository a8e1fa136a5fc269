"""Output paths (``--log``, ``--recover``, ``--plot``, ``--video``): exit 2 and one line naming the path.

Nothing is overwritten without ``--force``, no directory is created but the
default ``logs/``, and a write that fails during a run (a full disk, here a
file-size limit) ends the run with one line, not a traceback and a Rust panic.
"""

from __future__ import annotations

import errno
import os
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import pytest
from cli_support import cli
from runlog_synthetic import open_log, state_args, write_synthetic_run

from cosmos.errors import UsageError
from cosmos.runlog import read_log

PROGRAM = "MOVE BY (0, 0, 20 mm)\n"
LONG_PROGRAM = "MOVE BY (0, 0, 20 mm)\nWAIT 3 s\nMOVE BY (0, 0, -20 mm)\n"


@pytest.fixture
def program(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.cos"
    path.write_text(PROGRAM)
    return path


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_synthetic_run(tmp_path_factory.mktemp("outputs") / "run.mcap").path


def _refused(code: int, stdout: str, stderr: str, path: Path | str, says: str) -> None:
    assert code == 2, stderr
    assert stderr.startswith(f"{path}: ") and says in stderr and stderr.count("\n") == 1, stderr
    assert "Traceback" not in stderr


@pytest.mark.parametrize(
    "target, says",
    [
        ("existing", "already exists; pass --force to overwrite it"),
        ("directory", "is a directory"),
        ("/dev/full", "not a regular file"),
        ("/proc/self/run.mcap", "cannot write"),
        ("/sys/run.mcap", "cannot write"),
        ("missing/dir/run.mcap", "no such directory"),
    ],
)
def test_run_refuses_a_log_path_before_running(
    program: Path,
    tmp_path: Path,
    target: str,
    says: str,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Catches --log onto a device, /proc, /sys or a directory ending in a traceback (or a Rust
    panic for /dev/full), a missing directory created silently, and a log overwritten without a word."""
    path = {"existing": tmp_path / "old.mcap", "directory": tmp_path}.get(target, tmp_path / target)
    if target.startswith("/"):
        path = Path(target)
    if target == "existing":
        path.write_bytes(b"keep me")
    code, stdout, stderr = cli(["run", str(program), "--log", str(path)], capsys, monkeypatch)
    _refused(code, stdout, stderr, path, says)
    if target == "existing":
        assert path.read_bytes() == b"keep me"
    assert not (tmp_path / "missing").exists()


def test_force_overwrites_and_the_default_directory_is_made(
    program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches --force not reaching the writer, and the default logs/ no longer being created."""
    old = tmp_path / "old.mcap"
    old.write_bytes(b"replace me")
    code, stdout, stderr = cli(["run", str(program), "--log", str(old), "--force"], capsys, monkeypatch)
    assert code == 0, stderr
    assert not read_log(old).truncated
    monkeypatch.chdir(tmp_path)
    code, stdout, stderr = cli(["run", str(program)], capsys, monkeypatch)
    assert code == 0, stderr
    made = list((tmp_path / "logs").glob("tiny-*.mcap"))
    assert len(made) == 1 and stdout.strip() == f"log: {made[0].relative_to(tmp_path)}"


@pytest.mark.parametrize(
    "option, target, says",
    [
        ("--recover", "existing", "already exists; pass --force"),
        ("--recover", "/dev/full", "not a regular file"),
        ("--recover", "/proc/self/out.mcap", "cannot write"),
        ("--recover", "directory", "is a directory"),
        ("--recover", "missing/out.mcap", "no such directory"),
        ("--plot", "existing", "already exists; pass --force"),
        ("--plot", "directory", "is a directory"),
        ("--plot", "/sys/out.png", "cannot write"),
        ("--video", "existing.mp4", "already exists; pass --force"),
        ("--video", "/proc/self/out.mp4", "cannot write"),
    ],
)
def test_replay_refuses_an_output_path(
    log: Path,
    tmp_path: Path,
    option: str,
    target: str,
    says: str,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Catches --recover/--plot/--video onto an unwritable path ending in a traceback, and an
    existing file replaced without --force."""
    path = Path(target) if target.startswith("/") else tmp_path / target
    if target == "directory":
        path = tmp_path
    if target.startswith("existing"):
        path.write_bytes(b"keep me")
    code, stdout, stderr = cli(["replay", str(log), option, str(path)], capsys, monkeypatch)
    _refused(code, stdout, stderr, path, says)
    if target.startswith("existing"):
        assert path.read_bytes() == b"keep me"


def test_replay_force_overwrites_the_plot_and_the_recovered_log(
    log: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches --force not reaching the plot or the recovery."""
    png, out = tmp_path / "run.png", tmp_path / "out.mcap"
    png.write_bytes(b"old")
    out.write_bytes(b"old")
    argv = ["replay", str(log), "--plot", str(png), "--recover", str(out), "--force"]
    code, stdout, stderr = cli(argv, capsys, monkeypatch)
    assert code == 0, stderr
    assert png.read_bytes()[:4] == b"\x89PNG" and not read_log(out).truncated


def test_force_never_overwrites_what_the_command_reads(
    program: Path,
    log: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Catches ``cosmos run prog.cos --log prog.cos --force`` replacing the user's program with
    its own log (exit 0), and ``cosmos replay run.mcap --plot run.mcap --force`` the log with a
    picture, also through a symbolic link."""
    source = program.read_bytes()
    link = tmp_path / "link.cos"
    link.symlink_to(program)
    for target in (program, link):
        code, stdout, stderr = cli(
            ["run", str(program), "--log", str(target), "--force"], capsys, monkeypatch
        )
        _refused(code, stdout, stderr, target, "is a file this command reads; give the log another name")
    assert program.read_bytes() == source
    logged = log.read_bytes()
    for option, what in (("--plot", "the plot"), ("--video", "the video")):
        code, stdout, stderr = cli(["replay", str(log), option, str(log), "--force"], capsys, monkeypatch)
        _refused(code, stdout, stderr, log, f"is a file this command reads; give {what} another name")
    assert log.read_bytes() == logged


def test_a_write_that_fails_during_the_run_is_one_line_and_no_panic(tmp_path: Path) -> None:
    """Catches the writer's I/O error reaching Python as 'RuntimeError: FoxgloveError' and then a
    pyo3 PanicException at shutdown (the issue's --log /dev/full), and one stderr line per message."""
    program = tmp_path / "long.cos"
    program.write_text(LONG_PROGRAM)
    warm = tmp_path / "warm.cos"
    warm.write_text(PROGRAM)
    log = tmp_path / "run.mcap"
    # The child runs a short program first (on a cold cache that compiles and caches the
    # controller's kernels, files the limit would cut), then limits file sizes and runs.
    child = textwrap.dedent(
        """
        import resource, sys
        from cosmos.cli import main

        warm, warm_log, program, log = sys.argv[1:]
        try:
            sys.argv = ["cosmos", "run", warm, "--log", warm_log]
            main()
        except SystemExit as warmed:
            assert warmed.code == 0
        limit = 64 * 1024  # the run writes several times this
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        sys.argv = ["cosmos", "run", program, "--log", log]
        main()
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", child, str(warm), str(tmp_path / "warm.mcap"), str(program), str(log)],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")},
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr == f"{log}: cannot write the log: File too large\n"
    assert done.stdout == f"log: {tmp_path / 'warm.mcap'}\n"
    record = read_log(log)  # what was written before the limit is still a readable log
    assert record.truncated and len(record.state) > 0


def test_sigterm_during_shutdown_still_ends_with_a_complete_log_and_exit_143(tmp_path: Path) -> None:
    """Catches signals restored to their default as soon as the run stops: a SIGTERM landing while
    the log was being closed ended the process with -15, a log without its footer and no "log:"
    line."""
    import signal
    import threading
    import time

    program = tmp_path / "long.cos"
    program.write_text(LONG_PROGRAM)
    log = tmp_path / "run.mcap"
    child = subprocess.Popen(
        [sys.executable, "-m", "cosmos", "run", str(program), "--log", str(log)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")},
    )
    printed = threading.Event()
    lines: list[str] = []

    def read_stdout() -> None:
        assert child.stdout is not None
        for line in child.stdout:
            lines.append(line)
            if line.startswith("log: "):
                printed.set()

    reader = threading.Thread(target=read_stdout, daemon=True)
    reader.start()
    deadline = time.monotonic() + 300  # a cold cache compiles the kernels first
    while not log.exists() and child.poll() is None and time.monotonic() < deadline:
        time.sleep(0.002)
    sent = 0
    while not printed.is_set() and child.poll() is None and time.monotonic() < deadline:
        child.send_signal(signal.SIGTERM)  # before, during and after the stop, through the close
        sent += 1
        time.sleep(0.002)
    child.wait(timeout=300)
    reader.join(timeout=10)
    assert child.stderr is not None
    stderr = child.stderr.read()
    assert lines == [f"log: {log}\n"]  # the log was closed and named before any exit
    # 143 from the run's own status; -15 only from a signal sent after "log:" was printed and the
    # handlers restored (the reader thread notices the line a little late), which a shell also
    # reports as 143 and which can no longer cut the log.
    assert child.returncode in (128 + signal.SIGTERM, -signal.SIGTERM), (child.returncode, sent, stderr)
    assert "interrupted" in stderr and "Traceback" not in stderr
    record = read_log(log)
    assert not record.truncated
    last = record.events[-1]
    assert "interrupted" in (last.kind, last.reason)  # kind "interrupted", or "stopped" for that reason


def test_a_log_left_open_after_failed_writes_ends_quietly(tmp_path: Path) -> None:
    """Catches the Rust writer still open at interpreter shutdown: it printed 'error logging
    message' per message and ended in a pyo3 PanicException ('The Python interpreter is not
    initialized'); a log left open is now closed at exit, its write error kept."""
    child = textwrap.dedent(
        """
        import resource, sys
        from pathlib import Path
        from runlog_synthetic import open_log, state_args

        log = open_log(Path(sys.argv[1]), chunk_size=2048)
        resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))
        for k in range(3000):
            log.state(**state_args(k))
        print("left open")
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", child, str(tmp_path / "open.mcap")],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(__file__).parent), *sys.path])},
    )
    assert (done.returncode, done.stdout, done.stderr) == (0, "left open\n", "")
    assert len(read_log(tmp_path / "open.mcap").state) > 0


class _FullDisk:
    """A file whose writes fail as on a full disk (everything else goes to the real file)."""

    def __init__(self, stream: Any):
        self.stream = stream

    def write(self, data: bytes) -> int:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def __getattr__(self, name: str) -> Any:
        return getattr(self.stream, name)


def test_a_write_error_no_flush_reported_is_raised_by_close(tmp_path: Path) -> None:
    """Catches a write error lost when no flush came between it and the close (the run ended
    between two flushes): close must say it, once."""
    log = open_log(tmp_path / "run.mcap", chunk_size=1024)  # flushes only when told
    log._sink._stream = _FullDisk(log._sink._stream)
    for k in range(200):
        log.state(**state_args(k))  # chunks of 1 KiB fill and are written: the first write fails
    with pytest.raises(UsageError) as caught:
        log.close()
    assert caught.value.render() == f"{tmp_path / 'run.mcap'}: cannot write the log: No space left on device"
    log.close()  # once: a second close does nothing
