"""Playback of a logged run: in the MuJoCo viewer (``--view``) or rendered to MP4 (``--video``).

Both set the workcell's joint positions from the log's ``q`` at the playback's
frame times (linear interpolation between state samples) and show the scene
from the ``overview`` camera, with the obstacles logged on ``/scene`` drawn in
(:mod:`cosmos.replay.overlay`). ``--start`` picks the simulated time to start
from, ``--rate`` the speed (2: twice as fast as the run).

Video is rendered offscreen with :class:`mujoco.Renderer` (``MUJOCO_GL=egl``
unless set otherwise: it needs no display) and encoded to H.264 MP4 by the
ffmpeg binary that the ``imageio-ffmpeg`` package ships.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Generator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from cosmos.errors import CosmosError, UsageError
from cosmos.replay.overlay import draw, scene_timeline
from cosmos.runlog.output import check_output
from cosmos.runlog.printable import printable
from cosmos.runlog.reader import RunRecord, StateSeries

if TYPE_CHECKING:
    from cosmos.hand.playback_bodies import BodyTimeline
    from cosmos.plant import Plant

CAMERA = "overview"
"""Camera of the workcell scene that playback looks through."""
VIDEO_WIDTH, VIDEO_HEIGHT = 1024, 576
"""Video frame size [pixels]; within the scene's offscreen buffer, multiples of 16 for H.264."""


def prefer_headless_gl() -> None:
    """Use MuJoCo's EGL backend unless ``MUJOCO_GL`` says otherwise.

    MuJoCo reads ``MUJOCO_GL`` when it is first imported: call this before.
    """
    os.environ.setdefault("MUJOCO_GL", "egl")


@dataclass(frozen=True)
class Playback:
    """How to play a run back.

    Attributes:
        start_s: Simulated time of the first frame [s].
        rate: Simulated seconds shown per second of playback.
        fps: Frames per second of playback (video frame rate, viewer refresh).
    """

    start_s: float = 0.0
    rate: float = 1.0
    fps: float = 30.0


@dataclass(frozen=True)
class Video:
    """A video written by :func:`render_video`.

    Attributes:
        path: The MP4 file.
        frames: Number of frames.
        fps: Frame rate [1/s].
        start_s: Simulated time of the first frame [s].
        end_s: Simulated time of the last frame [s].
    """

    path: Path
    frames: int
    fps: float
    start_s: float
    end_s: float


MAX_FRAMES = 250_000
"""Most frames of a playback (over two hours of video at 30 fps): a log's times are untrusted."""


def frame_times(state_t: np.ndarray, playback: Playback) -> np.ndarray:
    """Simulated times of the playback's frames, from ``start_s`` to the last sample.

    Frame ``k`` shows simulated time ``start_s + k * rate / fps``: a run of ``T``
    seconds played from 0 gives ``floor(T * fps / rate) + 1`` frames.

    Args:
        state_t: Times of the state samples [s]. # (n,)
        playback: Start, rate and frame rate.

    Raises:
        CosmosError: If there are no samples.
        UsageError: If ``start_s`` is past the last sample, or the playback would
            have more than ``MAX_FRAMES`` frames.
    """
    if state_t.size == 0:
        raise CosmosError("the log has no state samples: nothing to play back")
    end_s = float(state_t[-1])
    if playback.start_s > end_s:
        raise UsageError(f"--start {playback.start_s:g} s is past the end of the run (t = {end_s:.3f} s)")
    step_s = playback.rate / playback.fps
    frames = np.floor((end_s - playback.start_s) / step_s + 1e-9) + 1
    if frames > MAX_FRAMES:
        raise UsageError(
            f"playing t = {playback.start_s:g} .. {end_s:.3f} s at {playback.rate:g}x takes {frames:,.0f} "
            f"frames, more than {MAX_FRAMES:,}: start later (--start) or play faster (--rate)"
        )
    count = int(frames)
    return playback.start_s + step_s * np.arange(count)  # (frames,)


def joint_positions_at(state: StateSeries, times_s: np.ndarray) -> np.ndarray:
    """Joint positions at ``times_s`` [rad], linearly interpolated between state samples.

    Samples with a non-finite ``q`` (a diverged controller) are skipped;
    times outside the samples take the first or last one.

    Returns:
        One row of the arm's joint angles per time. # (frames, n)

    Raises:
        CosmosError: If no sample has a finite ``q``.
    """
    finite = np.isfinite(state.q).all(axis=1) & np.isfinite(state.t)
    if not finite.any():
        raise CosmosError("the log has no state sample with finite joint positions")
    t, q = state.t[finite], state.q[finite]
    return np.column_stack([np.interp(times_s, t, q[:, j]) for j in range(q.shape[1])])


def _scene(record: RunRecord) -> Plant:
    """The workcell of the log's arm (``robot``; the PUMA 560 in logs before the Panda).

    A ``TOOL GRIPPER`` run's (metadata ``tool``) has its gripper and objects.
    """
    from cosmos.hand.playback_bodies import gripper_workcell
    from cosmos.plant import Plant
    from cosmos.robots import robot_named

    gripper = gripper_workcell(record)
    scene_xml = robot_named(record.metadata.get("robot", "puma560")).scene_xml
    return Plant(scene_xml) if gripper is None else Plant(scene_xml, edit_spec=gripper[0])


def _bodies(record: RunRecord) -> BodyTimeline | None:
    """A gripper run's objects and fingers over time (None for a peg run)."""
    from cosmos.hand.playback_bodies import BodyTimeline, gripper_workcell

    gripper = gripper_workcell(record)
    return None if gripper is None else BodyTimeline(record, gripper[1])


def _geom_names(plant: Plant) -> set[str]:
    """Names of the model's geoms: the fixtures that ``/scene`` also lists."""
    return {plant.model.geom(i).name for i in range(plant.model.ngeom)}


def _pose(plant: Plant, q: np.ndarray) -> None:
    import mujoco

    plant.data.qpos[: q.shape[0]] = q
    plant.data.qvel[:] = 0.0
    mujoco.mj_forward(plant.model, plant.data)


def _encoder(path: Path, fps: float) -> Generator[None, Any, None]:
    """A started imageio-ffmpeg writer generator for RGB frames of the video size."""
    try:
        import imageio_ffmpeg
    except ImportError:
        raise CosmosError(
            "--video needs the imageio-ffmpeg package (it ships ffmpeg): pip install imageio-ffmpeg"
        ) from None
    writer = imageio_ffmpeg.write_frames(
        str(path),
        (VIDEO_WIDTH, VIDEO_HEIGHT),
        fps=fps,
        codec="libx264",
        pix_fmt_in="rgb24",
        pix_fmt_out="yuv420p",
        quality=7,
        macro_block_size=16,
        ffmpeg_log_level="error",
    )
    writer.send(None)  # starts ffmpeg
    return writer


FrameCallback = Callable[[int, int], None]
"""Called after each video frame with (frames done, frames in all)."""


def check_video_name(path: Path) -> None:
    """Refuse a ``--video`` path that is not an MP4 file name.

    Raises:
        UsageError: If ``path`` does not end in ``.mp4`` or is a directory.
    """
    if path.suffix.lower() != ".mp4":
        raise UsageError(f"--video writes MP4: give a file name ending in .mp4 (got {path})")
    if path.is_dir():
        raise UsageError(f"--video {path}: is a directory; give a file name ending in .mp4")


def render_video(
    record: RunRecord,
    path: Path,
    playback: Playback,
    on_frame: FrameCallback | None = None,
    force: bool = False,
) -> Video:
    """Render the logged joint trajectory offscreen from the ``overview`` camera to an MP4 file.

    Software OpenGL (no GPU) takes ~0.1 to 0.4 s a frame at the video size.

    Raises:
        UsageError: If ``path`` does not end in ``.mp4``, ``--start`` is past the
            end, or the file cannot be written (see :mod:`cosmos.runlog.output`;
            ``force`` allows overwriting it).
        CosmosError: If the encoder is missing or offscreen rendering is not available.
    """
    check_video_name(path)
    check_output(path, what="the video", force=force)
    times = frame_times(record.state.t, playback)
    positions = joint_positions_at(record.state, times)  # (frames, n)
    prefer_headless_gl()
    import mujoco

    plant = _scene(record)
    obstacles = scene_timeline(record.path, _geom_names(plant))
    bodies = _bodies(record)
    try:
        renderer = mujoco.Renderer(plant.model, VIDEO_HEIGHT, VIDEO_WIDTH)
    except Exception as error:  # MuJoCo raises several kinds when no GL context can be made
        backend = os.environ.get("MUJOCO_GL", "")
        raise CosmosError(
            f"--video: cannot render offscreen (MUJOCO_GL={backend!r}): {error}; "
            "set MUJOCO_GL=egl (or osmesa) before running cosmos"
        ) from None
    with renderer:
        try:
            writer = _encoder(path, playback.fps)
            for k, (t_s, q) in enumerate(zip(times, positions, strict=True)):
                if on_frame is not None:
                    on_frame(k, times.size)
                if bodies is not None:
                    bodies.apply(plant.model, plant.data, float(t_s))
                _pose(plant, q)
                renderer.update_scene(plant.data, camera=CAMERA)
                draw(renderer.scene, obstacles.at(float(t_s)))
                # Shadows cost ~5x the rest of a frame in software GL; reflections stay.
                renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
                writer.send(np.ascontiguousarray(renderer.render()))
            writer.close()
        except (OSError, RuntimeError) as error:
            first_line = str(error).strip().splitlines()[0] if str(error).strip() else repr(error)
            raise UsageError(f"{path}: cannot write the video: {printable(first_line)}") from None
    return Video(path, int(times.size), playback.fps, float(times[0]), float(times[-1]))


def has_display() -> bool:
    """Whether a window can be opened (an X11 or Wayland display is named)."""
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def view(record: RunRecord, playback: Playback) -> None:
    """Play the run back in the MuJoCo viewer in real time (times ``rate``); return when it closes.

    The viewer opens looking through the ``overview`` camera's eye and can be
    turned with the mouse; the last frame stays until the window is closed.

    Raises:
        CosmosError: If there is no display.
        UsageError: If ``--start`` is past the end of the run.
    """
    if not has_display():
        raise CosmosError("no display: use --video FILE.mp4")
    times = frame_times(record.state.t, Playback(playback.start_s, playback.rate, fps=60.0))
    positions = joint_positions_at(record.state, times)  # (frames, n)
    import mujoco
    import mujoco.viewer

    plant = _scene(record)
    obstacles = scene_timeline(record.path, _geom_names(plant))
    bodies = _bodies(record)
    _pose(plant, positions[0])
    viewer_window = mujoco.viewer.launch_passive(
        plant.model, plant.data, show_left_ui=False, show_right_ui=False
    )
    with viewer_window as viewer:
        _look_like_camera(viewer.cam, plant, CAMERA)
        started = time.perf_counter()
        try:
            for t_s, q in zip(times, positions, strict=True):
                if not viewer.is_running():
                    return
                with viewer.lock():
                    if bodies is not None:
                        bodies.apply(plant.model, plant.data, float(t_s))
                    _pose(plant, q)
                    viewer.user_scn.ngeom = 0
                    draw(viewer.user_scn, obstacles.at(float(t_s)))
                viewer.sync()
                wait_s = started + (t_s - times[0]) / playback.rate - time.perf_counter()
                if wait_s > 0:
                    time.sleep(wait_s)
            while viewer.is_running():
                time.sleep(0.05)
        except KeyboardInterrupt:
            return


def _look_like_camera(cam: object, plant: Plant, name: str) -> None:
    """Point the viewer's free camera like the scene's fixed camera ``name``."""
    import mujoco

    model = plant.model
    camera = model.camera(name)
    rotation_camera_to_world = np.array(plant.data.cam_xmat[camera.id]).reshape(3, 3)
    forward = -rotation_camera_to_world[:, 2]  # cameras look along their -z
    position = np.array(plant.data.cam_xpos[camera.id])
    distance = 1.6  # [m] puts the look-at point near the table's middle for the overview camera
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE  # type: ignore[attr-defined]
    cam.lookat[:] = position + distance * forward  # type: ignore[attr-defined]
    cam.distance = distance  # type: ignore[attr-defined]
    cam.azimuth = float(np.degrees(np.arctan2(forward[1], forward[0])))  # type: ignore[attr-defined]
    cam.elevation = float(np.degrees(np.arcsin(np.clip(forward[2], -1.0, 1.0))))  # type: ignore[attr-defined]
