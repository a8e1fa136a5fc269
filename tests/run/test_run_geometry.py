"""The workcell geometry the acceptance tests judge against agrees with the scene.

run_support.py writes the fixtures out from the issue and the scene's
documentation; this checks them against the fixture frames cosmos reads from
the scene, so a moved fixture shows up here rather than as a puzzling failure.
"""

from __future__ import annotations

import numpy as np
from run_support import HOLE_MOUTH_M, SLOPE_CENTRE_M, SLOPE_NORMAL_OUT, TABLE_POINT_M, TABLE_TOP_Z_M

from cosmos.workcell import fixture_frames


def test_fixture_positions() -> None:
    """Table work point (on the top face), hole mouth and plate centre where the tests assume."""
    frames = fixture_frames()
    np.testing.assert_allclose(frames["table"].position, TABLE_POINT_M, atol=1e-9)
    assert TABLE_POINT_M[2] == TABLE_TOP_Z_M
    np.testing.assert_allclose(frames["hole"].position, HOLE_MOUTH_M, atol=1e-9)
    np.testing.assert_allclose(frames["slope"].position, SLOPE_CENTRE_M, atol=1e-9)


def test_fixture_z_axes_point_into_the_surfaces() -> None:
    """Table and hole frames point straight down; the slope's z is minus the plate's normal."""
    frames = fixture_frames()
    down = np.array([0.0, 0.0, -1.0])
    np.testing.assert_allclose(frames["table"].rotation[:, 2], down, atol=1e-9)
    np.testing.assert_allclose(frames["hole"].rotation[:, 2], down, atol=1e-9)
    np.testing.assert_allclose(frames["slope"].rotation[:, 2], -SLOPE_NORMAL_OUT, atol=1e-9)
