"""The peg holder of ``TOOL GRIPPER``'s workcell: a block with a loose bore, next to the hole.

World geoms (no frame: the plant names them ``world``, the supervision counts them as
fixtures and the log draws them with the pedestal): eight boxes around a bore of 11 mm
radius (1.1 mm of play around the 19.825 mm peg), 25 mm deep from the top face at
z 230 mm, on a bottom plate standing on the table; centred at
:data:`cosmos.hand.work_object.HOLDER_XY_M`.
"""

from __future__ import annotations

import math

import mujoco

from cosmos.hand.work_object import HOLDER_DEPTH_M, HOLDER_TOP_Z_M, HOLDER_XY_M

BORE_RADIUS_M = 0.011
OUTER_M = 0.025
"""Half the holder's width [m]."""
SECTORS = 8
TABLE_TOP_Z_M = 0.20


def add_holder(spec: mujoco.MjSpec) -> None:
    """Add the holder's geoms to the world body (module docstring)."""
    x0, y0 = HOLDER_XY_M
    bottom_z = HOLDER_TOP_Z_M - HOLDER_DEPTH_M
    half_wall = (OUTER_M - BORE_RADIUS_M) / 2
    half_width = BORE_RADIUS_M * math.tan(math.pi / SECTORS) + 0.002
    for k in range(SECTORS):
        angle = 2 * math.pi * k / SECTORS
        r = BORE_RADIUS_M + half_wall
        _fixture(
            spec,
            f"holder_wall{k}",
            (x0 + r * math.cos(angle), y0 + r * math.sin(angle), bottom_z + HOLDER_DEPTH_M / 2),
            (half_wall, half_width, HOLDER_DEPTH_M / 2),
            (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)),
        )
    base_half = (bottom_z - TABLE_TOP_Z_M) / 2
    _fixture(
        spec, "holder_base", (x0, y0, TABLE_TOP_Z_M + base_half), (OUTER_M, OUTER_M, base_half), (1, 0, 0, 0)
    )


def _fixture(
    spec: mujoco.MjSpec,
    name: str,
    pos: tuple[float, float, float],
    size: tuple[float, float, float],
    quat: tuple[float, float, float, float],
) -> None:
    geom = spec.worldbody.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=pos, size=size, quat=quat)
    geom.contype, geom.conaffinity = 1, 1
    geom.friction = (0.3, 0.005, 0.0001)
    geom.rgba = (0.55, 0.6, 0.7, 1.0)
