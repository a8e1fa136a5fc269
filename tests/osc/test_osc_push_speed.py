"""An INSERT's push aim and approach speed (cosmos.osc.push_speed), against their arithmetic."""

from __future__ import annotations

import pytest

from cosmos.osc.push_speed import approach_speed, push_aim


def test_the_push_aims_at_least_a_millimetre_per_second_under_its_speed() -> None:
    """0.9 SPEED, but at least 1 mm/s under it and never under half: catches the absolute margin
    dropped (SPEED 5 mm/s aimed at 4.5 mm/s and peaked at 6.65 on the realistic plant)."""
    assert push_aim(0.005, 0.9, 0.001) == pytest.approx(0.004)
    assert push_aim(0.020, 0.9, 0.001) == pytest.approx(0.018)
    assert push_aim(0.0015, 0.9, 0.001) == pytest.approx(0.00075)


def test_the_approach_runs_a_margin_under_the_tolerance_or_at_its_speed_when_slow() -> None:
    """``min(V, 1.1 V - 3 mm/s)`` from 8.6 mm/s up, V below: catches the approach left at its SPEED
    (seed 1's drawn arm ran it at 12.7 mm/s at SPEED 10) and one slowed where eq. 20 crawls (at
    2.5 mm/s for SPEED 5 it took 6-12 s)."""
    assert approach_speed(0.010, 0.003) == pytest.approx(0.008)
    assert approach_speed(0.020, 0.003) == pytest.approx(0.019)
    assert approach_speed(0.030, 0.003) == pytest.approx(0.030)
    assert approach_speed(0.100, 0.003) == pytest.approx(0.100)
    assert approach_speed(0.005, 0.003) == pytest.approx(0.005)
