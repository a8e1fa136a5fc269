"""The protective stops' tick on arrays listed by address, against the same tick in Python (issue 20).

:func:`cosmos.execution.supervision_kernel.supervise_listed` makes its views of ten arrays from
an int64 table of addresses (the supervisor's live buffers, and MuJoCo's contact records read as
int32) and runs :func:`~cosmos.execution.supervision_kernel.supervise_tick` on them. Here both
run tick by tick on the same streaky random inputs, the listed one compiled and
``supervise_tick``'s Python (its ``py_func``) on the arrays themselves: every tick's stop, the
supervision's state and the speed watch must agree exactly.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.execution import supervision_kernel as sk
from cosmos.execution.contact_kernel import IGNORED, LINK_ANY

JOINTS = 6
GEOMS = 8
RECORD = 13  # int32 per contact record: the pairs are its first two, as in MuJoCo's mjContact


def _listed(table: np.ndarray, at: int, array: np.ndarray) -> None:
    rows, columns = array.shape if array.ndim == 2 else (1, array.shape[0])
    table[at : at + 3] = (array.ctypes.data, rows, columns)


def _state(rng: np.random.Generator) -> np.ndarray:
    """A segment's supervision state: a line along x, path looked at on y and z, drives' limits."""
    state = np.zeros(sk.state_size(JOINTS))
    limits = rng.uniform(5.0, 50.0, JOINTS)
    state[sk.GONE_TICKS], state[sk.REACH2], state[sk.RATING2] = 50.0, 0.05**2, 100.0**2
    state[sk.FORCE_LIMIT2], state[sk.LOWEST], state[sk.LOOKS] = 20.0**2, limits.min(), 5.0
    state[sk.ALLOW_FIXTURE], state[sk.INHERITED] = rng.integers(0, 2), rng.integers(0, 2)
    state[sk.LOOK_AT_PATH] = 1.0
    state[sk.LINE : sk.LINE + sk.LINE_SIZE] = [0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.01]
    state[sk.SATURATED_AT : sk.SATURATED_AT + JOINTS] = limits
    return state


def test_the_listed_tick_is_the_tick_on_its_arrays() -> None:
    """Each stop (contact, force, path, drive, speed) and every tick's state agree with ``supervise_tick``
    run in Python on the arrays themselves. Catches an array listed in another's place (the torque
    read as the wrench), a contact record's pairs read at the wrong stride, a view of the wrong
    length, or the stop's joint or value not handed back."""
    found: set[int] = set()
    for seed in range(6):
        rng = np.random.default_rng(seed)
        kinds = rng.choice([IGNORED, 1, 2, LINK_ANY], size=(GEOMS, GEOMS), p=[0.7, 0.2, 0.05, 0.05])
        kinds = kinds.astype(np.int8)
        state, twin_state = _state(rng), None
        twin_state = state.copy()
        watch = np.concatenate(([20.0], np.full(JOINTS, 2.0), np.zeros(JOINTS)))
        unlimited = int(rng.integers(0, JOINTS))
        watch[1 + unlimited] = math.inf  # a joint without a limit
        fast = (unlimited + 1) % JOINTS
        twin_watch = watch.copy()
        axes = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        records = np.zeros((4, RECORD), dtype=np.int32)
        wrench, torque, position, qd = np.zeros(6), np.zeros(JOINTS), np.zeros(3), np.zeros(JOINTS)
        table = np.zeros(sk.TABLE_SIZE, dtype=np.int64)
        for at, array in (
            (sk.KINDS, kinds), (sk.WRENCH, wrench), (sk.TORQUE, torque), (sk.POSITION, position),
            (sk.STATE, state), (sk.AXES, axes), (sk.QD, qd), (sk.WATCH, watch),
        ):  # fmt: skip
            _listed(table, at, array)
        table[sk.GEOMS : sk.GEOMS + 3] = (records.ctypes.data, 0, RECORD)
        for tick in range(600):
            mode = (tick // 40 + seed) % 5  # streaks: calm, pushing, off its path, a drive held, a joint fast
            ncon = int(rng.integers(0, 5)) if rng.uniform() < 0.1 else 0
            records[:] = rng.integers(0, GEOMS, records.shape)
            wrench[:] = rng.normal(0.0, 25.0 if mode == 1 else 3.0, 6)
            torque[:] = rng.uniform(-1.0, 1.0, JOINTS) * state[sk.SATURATED_AT : sk.SATURATED_AT + JOINTS]
            if mode == 3:  # a drive at its limit, and now and then at minus it
                torque[seed] = (1.0 if tick % 7 else -1.0) * state[sk.SATURATED_AT + seed]
            position[:] = [rng.uniform(-0.02, 0.12), rng.normal(0.0, 0.06 if mode == 2 else 0.01), 0.0]
            qd[:] = rng.normal(0.0, 0.5, JOINTS)
            if mode == 4:
                qd[[fast, unlimited]] = rng.choice([-2.5, 2.5]), 9.0
            kind = sk.supervise_listed(ncon, table)
            expected = sk.supervise_tick.py_func(
                ncon, records[:, :2], kinds, wrench, torque, position, twin_state, axes, qd, twin_watch
            )
            which, value = state[sk.STOP_WHICH], state[sk.STOP_VALUE]
            assert (kind, which, value) == expected, (seed, tick)
            twin_state[sk.STOP_WHICH], twin_state[sk.STOP_VALUE] = which, value
            assert state.tolist() == twin_state.tolist() and watch.tolist() == twin_watch.tolist()
            found.add(kind)
    assert found == {sk.NO_STOP, sk.CONTACT_STOP, sk.FORCE_STOP, sk.PATH_STOP, sk.DRIVE_STOP, sk.SPEED_STOP}
