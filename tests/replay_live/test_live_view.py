"""`cosmos run --live` streams the run over foxglove-sdk's WebSocket server while the arm moves."""

from __future__ import annotations

import asyncio
import json
import os
import re
import struct
import sys
import time
from pathlib import Path

import websockets
from replay_live_logs import PROGRAM

from tests import foxglove_proto

SUBPROTOCOL = "foxglove.sdk.v1"  # Foxglove's WebSocket protocol, as the SDK's server speaks it
MESSAGE_DATA = 1  # binary opcode: subscription id (u32), log time (u64), payload


async def _watch(program: Path, log: Path) -> tuple[int, dict[str, list[bytes]], str]:
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "cosmos",
        "run",
        str(program),
        "--live",
        "--port",
        "0",
        "--rate",
        "0.5",
        "--log",
        str(log),
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
        env=dict(os.environ),
    )
    assert process.stderr is not None
    try:
        line = (await asyncio.wait_for(process.stderr.readline(), 120)).decode()
        found = re.search(r"ws://127\.0\.0\.1:(\d+)", line)
        assert found, line
        received: dict[str, list[bytes]] = {}
        topics: dict[int, str] = {}
        async with websockets.connect(f"ws://127.0.0.1:{found[1]}", subprotocols=[SUBPROTOCOL]) as ws:
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                try:
                    frame = await asyncio.wait_for(ws.recv(), 10)
                except websockets.ConnectionClosed:
                    break  # the run ended and the server stopped with it
                if isinstance(frame, str):
                    message = json.loads(frame)
                    if message["op"] == "advertise":
                        topics.update((c["id"], c["topic"]) for c in message["channels"])
                        subscriptions = [{"id": c["id"], "channelId": c["id"]} for c in message["channels"]]
                        await ws.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))
                elif frame[0] == MESSAGE_DATA:
                    (subscription,) = struct.unpack_from("<I", frame, 1)
                    received.setdefault(topics[subscription], []).append(bytes(frame[13:]))
        status = await asyncio.wait_for(process.wait(), 60)
        return status, received, line
    finally:
        if process.returncode is None:
            process.kill()
            await process.wait()


def test_live_view_streams_state_transforms_and_the_scene(tmp_path: Path) -> None:
    """Catches a --live that serves nothing while the arm moves (channels not in the server's
    context, samples held back until the end), a server left running after the run, a viewer
    connecting after the start seeing no arm (the scene sent once at t = 0), or a run that
    is not paced (it would end before a client could connect)."""
    program = tmp_path / "tiny.cos"
    program.write_text(PROGRAM)
    status, received, line = asyncio.run(_watch(program, tmp_path / "run.mcap"))
    assert status == 0, line
    states = [json.loads(data) for data in received["/cosmos/state"]]
    assert len(states) > 50
    times = [s["t"] for s in states]
    assert times == sorted(times) and times[-1] - times[0] > 0.5
    transforms = [foxglove_proto.decode("foxglove.FrameTransforms", d) for d in received["/tf"]]
    assert len(transforms) > 10
    assert {t["child_frame_id"] for t in transforms[-1]["transforms"]} >= {"link1", "tool"}
    scenes = [foxglove_proto.decode("foxglove.SceneUpdate", d) for d in received["/scene"]]
    shown = {e["id"] for scene in scenes for e in scene["entities"]}
    assert {"link1", "link6", "tool"} <= shown  # the arm, repeated for a late viewer


def test_ctrl_c_ends_run_with_status_130_and_a_readable_log(tmp_path: Path) -> None:
    """Catches Ctrl-C ending `cosmos run` with 0 or 1 (a shell script cannot tell an interrupted
    run from a finished or failed one), or leaving a log without its summary."""
    import signal
    import subprocess

    from cosmos.runlog import read_log

    program = tmp_path / "tiny.cos"
    program.write_text(PROGRAM)
    log = tmp_path / "run.mcap"
    command = [sys.executable, "-m", "cosmos", "run", str(program), "--live", "--port", "0"]
    process = subprocess.Popen(
        [*command, "--rate", "0.2", "--log", str(log)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert process.stderr is not None
        line = process.stderr.readline()  # printed once the run is under way
        assert "ws://127.0.0.1:" in line, line
        time.sleep(0.5)
        process.send_signal(signal.SIGINT)
        status = process.wait(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
    assert status == 130
    record = read_log(log)
    assert not record.truncated and 0 < record.end_time < 1.0  # stopped early; summary written
