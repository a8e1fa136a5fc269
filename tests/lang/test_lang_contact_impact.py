"""The check warns of a CONTACT or INSERT SPEED whose impact on steel would pass the wrist sensor's rating."""

from __future__ import annotations

import math

import pytest

from cosmos.capabilities import WRIST_SENSOR
from cosmos.lang import compile_program
from cosmos.workcell import fixture_frames

STEEL_N_PER_M = 3.3e5
"""The hole fixture's steel in an impact (cosmos/osc/landing.py: fitted on MuJoCo's contact force)."""
MASS_KG = {"puma560": 18.5, "panda": 8.8}
"""The arms' effective mass along a CONTACT over the hole (cosmos/osc/landing.py, measured)."""


def impact_warnings(source: str) -> list[str]:
    """The compiled program's warnings about meeting steel."""
    plan = compile_program(source, "p.cos", fixture_frames())
    return [w.message for w in plan.warnings if "would meet steel" in w.message]


@pytest.mark.parametrize(
    ("robot", "statement"),
    [("puma560", "CONTACT DOWN FORCE 5 N"), ("panda", "INSERT DOWN DEPTH 20 mm FORCE 10 N")],
)
def test_a_contact_speed_whose_impact_passes_the_sensors_rating_is_warned(robot: str, statement: str) -> None:
    """Catches ``cosmos check`` saying nothing of CONTACT DOWN ... SPEED 1 m/s (the new user's run hit
    the table at 134 N) or INSERT at 100 mm/s (223.7 N): a mass meeting a spring at ``v`` peaks at
    ``v sqrt(k m)``, so the warning comes just above the speed at which that is the sensor's 130 N
    rating (53 mm/s on the PUMA, 78 mm/s on the Panda), not just below it, and names the rating."""
    limit_mps = WRIST_SENSOR.force_n / math.sqrt(STEEL_N_PER_M * MASS_KG[robot])
    below, above = math.floor(limit_mps * 1e3) - 1, math.ceil(limit_mps * 1e3) + 1
    assert not impact_warnings(f"ROBOT {robot}\n{statement} SPEED {below} mm/s\n")
    (message,) = impact_warnings(f"ROBOT {robot}\n{statement} SPEED {above} mm/s\n")
    assert f"the wrist sensor's rating of {WRIST_SENSOR.force_n:g} N" in message
    assert f"at most {limit_mps * 1e3:.0f} mm/s" in message
    assert not impact_warnings(f"ROBOT {robot}\n{statement}\n")  # the default SPEED
