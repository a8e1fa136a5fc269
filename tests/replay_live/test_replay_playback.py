"""``cosmos replay --video`` and ``--view`` on a real run; the frame times and joint interpolation."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from replay_live_logs import PROGRAM, cosmos, decoded, run_to_log

from cosmos.errors import UsageError
from cosmos.replay.playback import VIDEO_HEIGHT, VIDEO_WIDTH, Playback, frame_times, joint_positions_at
from cosmos.runlog import read_log
from tests.cli_in_process import cosmos_in_process

STATE = "/cosmos/state"


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return run_to_log(tmp_path_factory.mktemp("playback"), PROGRAM)


def test_frame_times_step_by_rate_over_fps() -> None:
    times = frame_times(np.array([0.0, 0.5, 1.0]), Playback(start_s=0.25, rate=0.5, fps=10.0))
    # 0.05 s of the run per frame, from 0.25 s to 1.0 s inclusive: 16 frames.
    assert times.size == 16
    assert times[0] == pytest.approx(0.25) and times[-1] == pytest.approx(1.0)
    assert np.allclose(np.diff(times), 0.05)


def test_start_past_the_end_is_a_usage_error() -> None:
    with pytest.raises(UsageError, match="past the end"):
        frame_times(np.array([0.0, 1.0]), Playback(start_s=2.0))


def test_joint_positions_are_interpolated_between_samples(log: Path) -> None:
    record = read_log(log)
    states = decoded(log, STATE)
    t0, t1 = states[10]["t"], states[11]["t"]
    q0, q1 = np.array(states[10]["q"]), np.array(states[11]["q"])
    middle = joint_positions_at(record.state, np.array([t0, 0.25 * t0 + 0.75 * t1]))
    assert np.allclose(middle[0], q0, atol=1e-12)
    assert np.allclose(middle[1], 0.25 * q0 + 0.75 * q1, atol=1e-12)


def test_video_has_one_frame_per_step_of_rate_over_fps(log: Path, tmp_path: Path) -> None:
    imageio_ffmpeg = pytest.importorskip(
        "imageio_ffmpeg", reason="--video needs the imageio-ffmpeg package (not installed)"
    )
    out = tmp_path / "clip.mp4"
    start_s, rate, fps = 0.3, 2.0, 30.0
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    result = cosmos(
        "replay", str(log), "--video", str(out), "--start", str(start_s), "--rate", str(rate), env=env
    )
    assert result.returncode == 0, result.stdout + result.stderr
    end_s = decoded(log, STATE)[-1]["t"]
    expected = math.floor((end_s - start_s) * fps / rate + 1e-9) + 1
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(out))
    assert frames == expected
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    assert tuple(meta["size"]) == (VIDEO_WIDTH, VIDEO_HEIGHT)
    assert meta["fps"] == pytest.approx(fps)
    first = np.frombuffer(next(reader), dtype=np.uint8)
    reader.close()
    assert first.std() > 10  # a rendered scene, not a blank frame


def test_video_needs_an_mp4_name(log: Path, tmp_path: Path) -> None:
    """Catches a wrong --video name refused only after the whole summary was printed (a usage
    error must come before any work, as the other outputs' are)."""
    result = cosmos_in_process("replay", str(log), "--video", str(tmp_path / "clip.avi"))
    assert result.returncode == 2
    assert "ending in .mp4" in result.stderr
    assert result.stdout == ""


def test_view_without_a_display_says_to_use_video(log: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    result = cosmos_in_process("replay", str(log), "--view")
    assert result.returncode == 1
    assert "no display: use --video FILE.mp4" in result.stderr
    assert "Traceback" not in result.stderr


def test_rate_without_playback_is_a_usage_error(log: Path) -> None:
    result = cosmos_in_process("replay", str(log), "--rate", "2")
    assert result.returncode == 2
    assert "--rate and --start apply to --view and --video" in result.stderr
