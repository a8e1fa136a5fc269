"""The protective stops' look at MuJoCo's contact list, compiled (numba): one call per tick in contact.

A peg in its hole touches in 10 to 50 places at once; judging each contact in
Python cost the supervision 12 to 33 us a tick (half the servo tick's own cost).
Here each contact's kind is read from a table of geom pairs made once
(:func:`cosmos.execution.supervision.Supervisor`), in one call.
"""

from __future__ import annotations

import numpy as np
from numba.core import types

from cosmos.jit import kernel

IGNORED, TOOL_FIXTURE, TOOL_OBSTACLE, LINK_ANY = 0, 1, 2, 3
"""What a contact is, for the supervision: nothing of the arm (or the arm on itself), the tool on
a fixture, the tool on an obstacle, a link on anything."""

IntArray = np.ndarray


@kernel(
    types.Tuple((types.int64, types.boolean))(
        types.Array(types.int32, 2, "A"), types.Array(types.int8, 2, "C"), types.boolean, types.boolean
    )
)
def first_unexpected_contact(
    geom: IntArray, kinds: IntArray, allow_fixture: bool, allow_obstacle: bool
) -> tuple[int, bool]:
    """The first contact the statement does not expect, and whether the tool touches a fixture.

    Args:
        geom: The contacts' geom pairs (MuJoCo's ``data.contact.geom``). # (ncon, 2)
        kinds: Each pair of geoms' kind (``IGNORED`` ...). # (ngeom, ngeom)
        allow_fixture: The tool may touch the fixtures.
        allow_obstacle: The tool may touch obstacles (a guarded motion).

    Returns:
        ``(index, touching)``: the index of the first contact not allowed (-1 if none), and
        whether a contact before it (every contact if none) is the tool on a fixture.
    """
    touching = False
    for i in range(geom.shape[0]):
        kind = kinds[geom[i, 0], geom[i, 1]]
        if kind == IGNORED:
            continue
        if kind == TOOL_FIXTURE:
            touching = True
            if allow_fixture:
                continue
        elif kind == TOOL_OBSTACLE and allow_obstacle:
            continue
        return i, touching
    return -1, touching
