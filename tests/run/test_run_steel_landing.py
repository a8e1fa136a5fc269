"""A light CONTACT onto steel, on both arms (issue 14, item 5): the hole fixture's top face.

Each case is ``tests/run/contact_impact_grid.py``'s: the tool 16 mm off the hole's axis, above the
steel top face, ``CONTACT DOWN FORCE f SPEED v`` and ``WAIT 0.3 s``, the state logged at 1 kHz.
The peaks are read twice, independently: from the run's own log (the wrist sensor's push along the
approach) and from MuJoCo's contact forces on the tool at every physics step; both must stay under
the documented bar ``max(1.5 f, f + 5 N)`` in the first 0.3 s after the touch, the CONTACT must
succeed, and its hold must settle (``force settled``, not after its 3 s "not settled" bound).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from contact_impact_grid import bar_n, measure

SETTLED_S = 1.0
"""A hold that settles does so within this of its touch [s] (0.2-0.5 s on the table's grid)."""


@pytest.mark.parametrize(
    ("robot", "force_n", "speed_mmps", "seed"),
    [
        ("", 3.0, 5.0, "0"),
        ("", 3.0, 20.0, "0"),
        ("panda", 3.0, 5.0, "0"),
        ("panda", 30.0, 20.0, "ideal"),
    ],
)
def test_steel_landing_meets_the_bar_and_settles(
    tmp_path: Path, robot: str, force_n: float, speed_mmps: float, seed: str
) -> None:
    """The PUMA's and the Panda's CONTACT DOWN onto the hole's top face, light and heavy.

    Catches, on the PUMA, a landing speed chosen without the FORCE (3.8 mm/s whatever it is):
    FORCE 3 N at SPEED 5 mm/s (realistic seed 0) touched at 3.6 mm/s and peaked at 9.3 N logged,
    9.7 N in MuJoCo (bar 8 N); and the push's damping acting on the velocity observer's answer to
    encoder counts once landed: FORCE 3 N at 20 mm/s rang between 1.3 and 4.4 N and was "not
    settled to 0.5 N in 3 s". On the Panda, the held push's proportional gain over 1 on steel:
    FORCE 30 N (ideal plant) rang from 28 N into bounces between 0 and 62 N and failed ("force
    did not settle"); its 3 N landing is the light case, met before and kept.
    """
    figures = measure(
        "hole", force_n, speed_mmps, int(seed) if seed != "ideal" else 0, seed == "ideal", tmp_path, robot
    )
    bar = bar_n(force_n)
    described = f"{figures}"
    assert figures.ok, described
    assert figures.peak_log_n < bar, f"logged peak over {bar:g} N: {described}"
    assert figures.peak_contact_n < bar, f"MuJoCo's contact peak over {bar:g} N: {described}"
    assert math.isfinite(figures.settle_s) and figures.settle_s < SETTLED_S, described
