"""The pads' sensor noise: the same numbers, reading after reading, as one draw from the run's seed each."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cosmos.hand.fingers import NOISE_BLOCK, Fingers
from cosmos.realism.wrist_sensor import BIAS_FORCE_STD_N, FORCE_NOISE_STD_N
from tests.hand.gripper_support import gripper_session


def test_the_pads_noise_is_the_seeds_draw_after_draw(tmp_path: Path) -> None:
    """The noise is drawn a block of readings at a time (one draw a reading cost 3 us, every tick of a
    GRASP and every slip check). Catches a block that changes the numbers a run reads (its logged
    finger forces and a GRASP's outcome would then differ from the same seed's before), a reading
    skipped or read twice at a block's end, or the bias added in another order."""
    readings = 2 * NOISE_BLOCK + 5  # across two blocks' ends
    with gripper_session(tmp_path, ideal=False) as session:
        fingers = Fingers(session.plant.model, session.plant.data, 11, realistic=True)
        fingers.filtered[:] = (12.5, 13.25)
        got = [(r.force_left_n, r.force_right_n) for r in (fingers.read() for _ in range(readings))]
    draws = np.random.default_rng([11, 17])
    bias = draws.normal(0.0, BIAS_FORCE_STD_N, size=2)
    filtered = np.array([12.5, 13.25])
    expected = [
        tuple((filtered + bias + draws.normal(0.0, FORCE_NOISE_STD_N, size=2)).tolist())
        for _ in range(readings)
    ]
    assert got == expected
