"""Objects of the workcell that the gripper can pick up: what a program's ``OBJECT`` declares.

No simulator here (the language builds these); :mod:`cosmos.hand.object_scene` makes each
one a free MuJoCo body.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

DEFAULT_OBJECT_FRICTION = 0.5
"""Sliding friction of an object that names none (wood or plastic on the fixtures' 0.3)."""


class ObjectShape(Enum):
    """The shape of an object."""

    BOX = "box"
    CYLINDER = "cylinder"


@dataclass(frozen=True)
class WorkObject:
    """A rigid, uniform object, free in the workcell.

    Attributes:
        name: Its name in programs (``GRASP block``) and the MuJoCo body's.
        shape: Box or cylinder (axis along its frame's z).
        half_extents_m: Half sizes along its frame's x, y, z [m]; a cylinder's x and y are its
            radius.
        mass_kg: Its mass [kg]; uniform density.
        position_m: Its centre at the start, world [m].
        quat_wxyz: Its orientation at the start, frame to world (w, x, y, z).
        friction: Sliding friction coefficient of its surface.
        base_in_body_m: Its frame's origin, the centre of the face it stood on when declared,
            in its body's axes from its centre [m]: the point a MOVE of the held object moves.
        peg_end: A cylinder whose base end is the welded peg's (a 1.5 mm chamfer of 32 facets
            that touch the hole's geoms) and whose contacts are the tool's soft steel ones:
            the shipped peg (:data:`SHIPPED_PEG`).
    """

    name: str
    shape: ObjectShape
    half_extents_m: tuple[float, float, float]
    mass_kg: float
    position_m: tuple[float, float, float]
    quat_wxyz: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    friction: float = DEFAULT_OBJECT_FRICTION
    base_in_body_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    peg_end: bool = False

    def inertia_diagonal_kgm2(self) -> tuple[float, float, float]:
        """Principal moments about the centre, its frame's axes [kg m^2] (uniform solid)."""
        a, b, c = self.half_extents_m
        m = self.mass_kg
        if self.shape is ObjectShape.BOX:
            return (m * (b * b + c * c) / 3.0, m * (a * a + c * c) / 3.0, m * (a * a + b * b) / 3.0)
        radial = m * (3.0 * a * a + 4.0 * c * c) / 12.0  # height 2c
        return (radial, radial, m * a * a / 2.0)


PEG_RADIUS_M = 0.0099125
"""The shipped peg's radius: the welded peg's (c11 middle, 19.825 mm)."""
PEG_LENGTH_M = 0.100
PEG_MASS_KG = 7850.0 * 3.141592653589793 * PEG_RADIUS_M**2 * PEG_LENGTH_M
"""Steel, 7850 kg/m^3: 0.242 kg."""
HOLDER_XY_M = (0.60, 0.27)
"""The peg holder's bore on the table, 120 mm from the hole along y [m]."""
HOLDER_TOP_Z_M = 0.23
HOLDER_DEPTH_M = 0.025
"""Its top face and the depth of its bore [m]: the peg stands 75 mm out of it."""
STEEL_FRICTION = 0.45

SHIPPED_PEG = WorkObject(
    name="peg",
    shape=ObjectShape.CYLINDER,
    half_extents_m=(PEG_RADIUS_M, PEG_RADIUS_M, PEG_LENGTH_M / 2),
    mass_kg=PEG_MASS_KG,
    position_m=(HOLDER_XY_M[0], HOLDER_XY_M[1], HOLDER_TOP_Z_M - HOLDER_DEPTH_M + PEG_LENGTH_M / 2),
    quat_wxyz=(0.0, 1.0, 0.0, 0.0),  # z down: its frame is the hole's and the table's
    friction=STEEL_FRICTION,
    base_in_body_m=(0.0, 0.0, PEG_LENGTH_M / 2),  # the chamfered end, at the bore's bottom
    peg_end=True,
)
"""The peg of ``TOOL GRIPPER``'s workcell, standing chamfered end down in its holder next to the
hole; its frame (the centre of that end, z down) goes where a program MOVEs or INSERTs it."""

TABLE_TOP_Z_M = 0.20
"""The table top (``cosmos/models/*/scene.xml``, ``table_top``) [m]."""


def _block(
    name: str, size_m: tuple[float, float, float], mass_kg: float, xy_m: tuple[float, float]
) -> WorkObject:
    half = (size_m[0] / 2, size_m[1] / 2, size_m[2] / 2)
    return WorkObject(
        name=name,
        shape=ObjectShape.BOX,
        half_extents_m=half,
        mass_kg=mass_kg,
        position_m=(xy_m[0], xy_m[1], TABLE_TOP_Z_M + half[2]),
        quat_wxyz=(0.0, 1.0, 0.0, 0.0),  # z down, as an OBJECT declared AT table: its base is its frame
        base_in_body_m=(0.0, 0.0, half[2]),
    )


SHIPPED_BLOCKS = (
    _block("block_a", (0.040, 0.030, 0.050), 0.5, (0.44, 0.02)),
    _block("block_b", (0.030, 0.030, 0.030), 0.2, (0.44, 0.10)),
    _block("block_c", (0.060, 0.040, 0.040), 1.0, (0.44, 0.18)),
)
"""The blocks of ``TOOL GRIPPER``'s workcell, standing on the table in a row along y at
x 440 mm, 160 mm and more from the hole, the peg's holder and the table point (off the
shipped programs' paths): ``block_a`` 40 x 30 x 50 mm 0.5 kg (pick_and_place.cos's block),
``block_b`` a 30 mm cube of 0.2 kg, ``block_c`` 60 x 40 x 40 mm 1 kg; the first size is along
x, the last the height. Each frame is the centre of its base, z down (the table's axes)."""

SHIPPED_OBJECTS = (SHIPPED_PEG, *SHIPPED_BLOCKS)
"""The objects ``TOOL GRIPPER``'s workcell comes with: the peg in its holder, the blocks."""
