"""Obstacles logged on /scene show in playback when and where logged; fixtures are not drawn twice."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from replay_live_logs import PROGRAM, copy_with_source, cosmos, run_to_log

from cosmos.plant import Plant
from cosmos.replay.overlay import ShapeKind, scene_timeline
from cosmos.runlog.foxglove import SCENE_TOPIC, scene_update
from cosmos.runlog.scene import Box, Color, Sphere, entity

MAGENTA = Color(1.0, 0.0, 1.0, 1.0)
BOX = Box("crate", (0.55, -0.25, 0.30), (0.20, 0.10, 0.16), color=MAGENTA)
BALL_AT = ((0.6, 0.1, 0.35), (0.6, 0.2, 0.35))


def _ns(t_s: float) -> int:
    return round(t_s * 1e9)


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("overlay")
    plain = run_to_log(directory, PROGRAM)
    updates = [
        (0.1, [BOX], []),
        (0.2, [Sphere("ball", BALL_AT[0], 0.03)], []),
        (0.4, [Sphere("ball", BALL_AT[1], 0.03)], []),
        (0.5, [], ["crate"]),
    ]
    extra = [
        (SCENE_TOPIC, _ns(t), scene_update(_ns(t), [entity(p, _ns(t)) for p in add], remove).encode())
        for t, add, remove in updates
    ]
    return copy_with_source(plain, directory / "obstacles.mcap", extra=extra)


def test_timeline_follows_adds_moves_and_removals(log: Path) -> None:
    model = Plant().model
    timeline = scene_timeline(log, {model.geom(i).name for i in range(model.ngeom)})
    assert timeline.at(0.05) == ()  # the fixtures logged at t = 0 are the model's own geoms
    (crate,) = timeline.at(0.15)
    assert crate.kind is ShapeKind.BOX
    assert np.allclose(crate.half_sizes, np.array(BOX.size) / 2)
    assert np.allclose(crate.position, BOX.position)
    assert np.allclose(crate.rotation_to_world, np.eye(3))
    assert np.allclose(crate.rgba, MAGENTA)
    balls = [s for s in timeline.at(0.45) if s.kind is ShapeKind.SPHERE]
    assert len(timeline.at(0.45)) == 2 and np.allclose(balls[0].position, BALL_AT[1])
    (ball,) = timeline.at(0.6)
    assert np.allclose(ball.half_sizes, 0.03)


def _magenta_pixels(frame: np.ndarray) -> int:
    r, g, b = (frame[..., i].astype(int) for i in range(3))
    return int(((r > 180) & (b > 180) & (g < 90)).sum())


def test_video_shows_the_obstacle_while_it_is_in_the_scene(log: Path, tmp_path: Path) -> None:
    imageio_ffmpeg = pytest.importorskip(
        "imageio_ffmpeg", reason="--video needs the imageio-ffmpeg package (not installed)"
    )
    out = tmp_path / "obstacles.mp4"
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    result = cosmos("replay", str(log), "--video", str(out), env=env)
    assert result.returncode == 0, result.stdout + result.stderr
    reader = imageio_ffmpeg.read_frames(str(out))
    width, height = next(reader)["size"]
    frames = [np.frombuffer(data, dtype=np.uint8).reshape(height, width, 3) for data in reader]
    # 30 fps from t = 0: frame 1 is t = 0.033 s (no crate), 9 is 0.3 s (crate), 18 is 0.6 s (removed).
    assert _magenta_pixels(frames[1]) < 50
    assert _magenta_pixels(frames[9]) > 2000
    assert _magenta_pixels(frames[18]) < 50
