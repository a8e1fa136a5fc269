"""A run killed with SIGKILL: its log is read up to the last flush and can be recovered."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from runlog_synthetic import state_args

from cosmos.runlog import read_log, recover

FLUSHED = 300

CHILD = textwrap.dedent(
    f"""
    import sys
    from pathlib import Path
    from runlog_synthetic import open_log, state_args

    log = open_log(Path(sys.argv[1]), chunk_size=int(sys.argv[2]))
    log.event(0.0, "start", line=2, statement="MOVE TO hole + (0, 0, 80 mm)")
    for k in range({FLUSHED}):
        log.state(**state_args(k))
    log.flush()
    print("flushed", flush=True)
    k = {FLUSHED}
    while True:  # keeps writing, chunk after chunk, until killed
        log.state(**state_args(k))
        k += 1
    """
)


@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL is POSIX")
@pytest.mark.parametrize(
    "chunk_size",
    [
        1 << 30,  # nothing reaches the file after the flush: exactly the flushed states
        2048,  # chunks keep closing after the flush: those are read too
    ],
)
def test_killed_run_leaves_a_readable_recoverable_log(tmp_path: Path, chunk_size: int) -> None:
    path = tmp_path / "killed.mcap"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(__file__).parent), *sys.path])}
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(path), str(chunk_size)],
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "flushed"
        size_at_flush = path.stat().st_size
        deadline = time.monotonic() + (0.5 if chunk_size > 2048 else 20.0)
        while path.stat().st_size < size_at_flush + 20_000 and time.monotonic() < deadline:
            time.sleep(0.05)  # let it write past the flush
    finally:
        child.send_signal(signal.SIGKILL)
        child.wait(timeout=30)
    assert child.returncode == -signal.SIGKILL

    record = read_log(path)
    assert record.truncated
    assert record.metadata["program"] == "programs/peg.cos"
    if chunk_size > 2048:
        assert len(record.state) == FLUSHED
    else:
        assert len(record.state) > FLUSHED
    written = [state_args(k)["wrench"] for k in range(len(record.state))]
    assert np.allclose(record.state.wrench, written, atol=0.5e-6 + 1e-12)
    assert np.all(np.diff(record.state.t) > 0)

    out = tmp_path / "recovered.mcap"
    recover(path, out)
    with open(out, "rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None and summary.statistics is not None
    assert summary.statistics.message_count == sum(record.message_counts.values())
    recovered = read_log(out)
    assert not recovered.truncated
    assert len(recovered.state) == len(record.state)
