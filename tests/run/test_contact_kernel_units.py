"""The protective stops' compiled look at the contact list against the rules written out per contact."""

from __future__ import annotations

import numpy as np

from cosmos.execution.contact_kernel import IGNORED, TOOL_FIXTURE, TOOL_OBSTACLE, first_unexpected_contact
from cosmos.execution.contact_roles import Role, pair_kind


def _expected(
    pairs: list[tuple[int, int]], roles: list[Role], allow_fixture: bool, allow_obstacle: bool
) -> tuple[int, bool]:
    """The rule of module ``supervision``, contact by contact, from the roles themselves."""
    touching = False
    for index, (g1, g2) in enumerate(pairs):
        kind = pair_kind(roles[g1], roles[g2])
        if kind == IGNORED:
            continue
        if kind == TOOL_FIXTURE:
            touching = True
            if allow_fixture:
                continue
        elif kind == TOOL_OBSTACLE and allow_obstacle:
            continue
        return index, touching
    return -1, touching


def test_first_unexpected_contact_follows_the_rules_in_order() -> None:
    """Catches a later contact named than the first one not allowed (the stop would name the wrong
    part), the tool-on-fixture flag missed when the fixture is allowed (an inherited contact then
    never counts as still there), a swapped geom pair, and a strided contact list misread (MuJoCo's
    ``data.contact.geom`` is a view into its contact records, not a contiguous array)."""
    rng = np.random.default_rng(7)
    roles = [Role(int(r)) for r in rng.integers(0, len(Role), size=30)]
    role_array = np.array([int(r) for r in roles], dtype=np.int64)
    kinds = np.array([[pair_kind(Role(a), Role(b)) for b in role_array] for a in role_array], dtype=np.int8)
    records = np.zeros(60, dtype=[("dist", "f8"), ("geom", "i4", (2,)), ("frame", "f8", (9,))])
    for _ in range(300):
        ncon = int(rng.integers(0, 60))
        pairs = rng.integers(0, 30, size=(ncon, 2))
        records["geom"][:ncon] = pairs
        geom = records["geom"][:ncon]  # strided, as MuJoCo's
        assert not geom.flags.c_contiguous or ncon <= 1
        for allow_fixture in (False, True):
            for allow_obstacle in (False, True):
                got = first_unexpected_contact(geom, kinds, allow_fixture, allow_obstacle)
                want = _expected([tuple(p) for p in pairs.tolist()], roles, allow_fixture, allow_obstacle)
                assert (int(got[0]), bool(got[1])) == want
