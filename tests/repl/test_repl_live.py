"""`:live` in the REPL serves the session on loopback, paces the arm in real time, stops at the end."""

from __future__ import annotations

import io
import re
import socket
import time
from pathlib import Path

from cosmos.repl.app import ReplApp


def test_live_serves_paces_and_stops_with_the_session(tmp_path: Path) -> None:
    """Catches :live starting no server (or not on 127.0.0.1), the arm not paced to the wall clock
    once live, or the server left listening after the session ends."""
    out = io.StringIO()
    app = ReplApp(tmp_path / "s.mcap", out, stdin=io.StringIO(":live 0\n:live\nWAIT 0.6 s\n"))
    started = time.monotonic()
    assert app.run() == 0
    elapsed = time.monotonic() - started
    text = out.getvalue()
    ports = re.findall(r"live: ws://127\.0\.0\.1:(\d+)", text)
    assert len(ports) == 2 and ports[0] == ports[1], text  # the second :live names the same server
    assert elapsed >= 0.55, elapsed  # the WAIT took its simulated time on the wall clock
    with socket.socket() as probe:
        assert probe.connect_ex(("127.0.0.1", int(ports[0]))) != 0  # stopped with the session


def test_live_with_a_bad_port_says_how_to_use_it(tmp_path: Path) -> None:
    """Catches a bad :live argument ending in a traceback instead of a usage line."""
    out = io.StringIO()
    app = ReplApp(tmp_path / "s.mcap", out, stdin=io.StringIO(":live 99999\n"))
    assert app.run() == 0
    assert "usage: :live [PORT]" in out.getvalue() and "Traceback" not in out.getvalue()
