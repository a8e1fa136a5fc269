"""The fixtures drawn in the run log's 3D view: every fixture geom, and nothing else."""

import math

import numpy as np

from cosmos.execution.fixtures import fixture_primitives
from cosmos.plant import Plant
from cosmos.runlog.scene import Box


def test_fixture_primitives_are_the_table_hole_and_plate():
    primitives = {p.id: p for p in fixture_primitives(Plant())}
    # The scene file's comments: a table top 0.64 x 1.0 x 0.1 m with its top at z = 0.2 m,
    # four legs, 16 sectors of three boxes and a bottom for the hole, one tilted plate.
    assert len(primitives) == 1 + 4 + 16 * 3 + 1 + 1
    assert all(isinstance(p, Box) for p in primitives.values())
    assert not {"floor", "pedestal", "peg"} & primitives.keys()
    top = primitives["table_top"]
    np.testing.assert_allclose(top.size, (0.64, 1.0, 0.1), atol=1e-12)
    np.testing.assert_allclose(top.position, (0.62, -0.10, 0.15), atol=1e-12)
    walls = [p for name, p in primitives.items() if name.startswith("hole_wall")]
    radii = [math.dist(w.position[:2], (0.60, 0.15)) for w in walls]
    np.testing.assert_allclose(radii, 0.02751625, atol=1e-9)  # r 10.0325 .. 45 mm about the hole's axis
    w, x, y, z = primitives["slope_plate"].quat_wxyz
    tilt = math.degrees(2 * math.atan2(math.hypot(x, y), abs(w)))
    assert abs(tilt - 20.0) < 1e-6
