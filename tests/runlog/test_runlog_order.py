"""The log file holds messages in the order they were logged, though samples are written in batches."""

from pathlib import Path

import numpy as np
from mcap.reader import make_reader
from runlog_synthetic import open_log, segment_args, state_args

from cosmos.runlog.scene import Sphere


def test_messages_logged_among_waiting_samples_keep_their_place(tmp_path: Path) -> None:
    """An event, a segment or a scene update logged while state samples wait for their batch is
    written after those samples and before any later one, also across batches and at the close.

    Catches a staged message written before the samples it followed (the order the events were
    logged in, seen from the states, lost), after later samples, or dropped at a batch's end.
    """
    path = tmp_path / "order.mcap"
    log = open_log(path)
    expected: list[tuple[str, int]] = []

    def ns(t: float) -> int:
        return round(t * 1e9)

    log.scene(0.0, add=[Sphere("ball", (0.4, 0.25, 0.5), 0.06)])  # nothing waits: written at once
    expected.append(("/scene", 0))
    marks = {3: "event", 63: "segment", 64: "event", 100: "scene", 150: "event"}  # 64 samples a batch
    for k in range(151):
        args = state_args(k)
        t = args["t"]
        log.state(**args)
        expected.append(("/cosmos/state", ns(t)))
        if k % 5 == 0:
            log.transforms(t, np.tile([0.1, 0.2, 0.3], (7, 1)), np.tile([1.0, 0, 0, 0], (7, 1)))
            expected.append(("/tf", ns(t)))
        mark = marks.get(k)
        if mark == "event":
            log.event(t, "contact", line=3, statement="CONTACT DOWN", reason=f"at sample {k}")
            expected += [("/cosmos/event", ns(t)), ("/cosmos/log", ns(t))]
        elif mark == "segment":
            log.segment(t, **segment_args(1))
            expected.append(("/cosmos/segment", ns(t)))
        elif mark == "scene":
            log.scene(t, remove=["ball"])
            expected.append(("/scene", ns(t)))
    log.close()
    with open(path, "rb") as stream:
        written = [
            (channel.topic, message.log_time)
            for _, channel, message in make_reader(stream).iter_messages(log_time_order=False)
        ]
    assert written == expected
