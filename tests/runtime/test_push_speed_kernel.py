"""The compiled INSERT speed servo (cosmos.runtime.kernels.push_speed) against cosmos.osc.push_speed."""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.push_speed import follow_the_tool, speed_reference_step
from cosmos.osc.unified import speed_limited_push
from cosmos.runtime.kernels import push_speed as pk

DT_S, KV, RATE = 0.001, 300.0, 60.0
SEEDS = range(6)


def test_the_reference_rises_at_its_rate_from_the_tools_speed_and_stops_at_the_aim() -> None:
    """From the tool's speed, ``rate aim`` per second, its rise fed forward, held at the aim: catches
    a reference that starts at zero under a moving tool (a landing would be braked) or at the aim
    (the step it exists to avoid), and one that passes its aim."""
    aim = 0.010
    reference, rise = speed_reference_step(None, aim, 0.004, RATE, DT_S)
    assert rise == pytest.approx(RATE * aim) and reference == pytest.approx(0.004 + RATE * aim * DT_S)
    for _ in range(50):
        reference, rise = speed_reference_step(reference, aim, 0.0, RATE, DT_S)
    assert reference == aim and rise == 0.0
    assert speed_reference_step(None, aim, -0.002, RATE, DT_S)[0] == pytest.approx(RATE * aim * DT_S)
    assert follow_the_tool(0.02, aim) == aim and follow_the_tool(-0.001, aim) == 0.0


def _line(rng: np.random.Generator) -> np.ndarray:
    line = rng.normal(size=3)
    return line / np.linalg.norm(line)


@pytest.mark.parametrize("seed", SEEDS)
def test_the_push_at_its_speed_is_its_reference(seed: int) -> None:
    """The push capped on its stepped reference (binding on odd seeds), the reference following the
    tool where it does not bind. Catches the cap left on the aim (a dip's recovery stepped), the
    rise not fed forward, the reference left up while the push is at its force."""
    rng = np.random.default_rng(seed)
    goal = np.concatenate((-15.0 * _line(rng), np.zeros(3)))
    n = goal[:3] / 15.0
    f2a = np.eye(6) / 10.8
    velocity, sensed = rng.normal(0.0, 0.003, 6), rng.normal(0.0, 2.0, 6)
    aim, k_vf = 0.009, 30.0
    reference, rise = speed_reference_step(0.004, aim, float(n @ velocity[:3]), RATE, DT_S)
    assert 0.0 < rise and reference < aim  # mid-rise
    along = float(n @ velocity[:3])
    allowed = float(n @ sensed[:3]) + 10.8 * (rise + KV * (reference - along) + k_vf * along)
    feedback = np.zeros(6)
    feedback[:3] = (allowed + (20.0 if seed % 2 else -20.0)) * n
    expected, limited = speed_limited_push(feedback, goal, sensed, velocity, f2a, reference, KV, k_vf, rise)
    cruise = np.array((0.0, 0.0, 0.004, 1.0))
    got = feedback.copy()
    bound = pk.push_at_speed_into(
        got, goal, sensed, velocity, f2a, np.array((k_vf, KV, aim)), RATE, cruise, DT_S
    )
    assert bound == limited
    assert limited == bool(seed % 2)
    np.testing.assert_allclose(got, expected, atol=1e-9)
    assert cruise[2] == pytest.approx(reference if limited else follow_the_tool(along, aim))
