"""The compiled JSON kernels against Python's own ``%`` formatting of the same templates."""

import json

import numpy as np
import pytest

from cosmos.runlog.schemas import STATE_VECTORS, STATE_WIDTH
from cosmos.runlog.text_kernel import (
    render_states,
    stage_state,
    stage_transform,
    time_nanoseconds,
)
from cosmos.runlog.text_template import (
    STATE_NOT_EXACT,
    STATE_TIME_OUTSIDE,
    STATE_WRITTEN,
    TIME_LIMIT_S,
    Template,
)

STATE_FORMAT = (
    '{"t":%.9f,'
    + ",".join(f'"{name}":[' + ",".join(["%de-6"] * n) + "]" for name, n in STATE_VECTORS)
    + ',"segment":%d,"line":%d}'
)


def awkward_values(rng: np.random.Generator, n: int) -> np.ndarray:
    """Values of every size, with exact halves of a micro-unit and integers among them."""
    scale = 10.0 ** rng.integers(-9, 12, n)
    values = rng.uniform(-1, 1, n) * scale
    values[::7] = rng.integers(-3_000_000, 3_000_000, values[::7].size) * 0.5e-6  # ties: half to even
    values[::11] = 0.0
    values[1::13] = -0.0
    values[2::17] = 999_999_999_999.9  # just below the limit
    return values


def render(
    rows: np.ndarray, times: np.ndarray, labels: np.ndarray
) -> tuple[list[bytes], list[int], list[int]]:
    n = len(times)
    template = Template.from_format(STATE_FORMAT.replace("%.9f", "%d"))
    out = np.zeros(n * template.max_bytes, dtype=np.uint8)
    status = np.full(n, -1, dtype=np.int64)
    offsets = np.zeros(n + 1, dtype=np.int64)
    times_ns = np.zeros(n, dtype=np.int64)
    end = render_states(
        out, rows, times, labels, n, template.literals, template.bounds, status, offsets, times_ns
    )
    blob = out[:end].tobytes()
    return [blob[offsets[i] : offsets[i + 1]] for i in range(n)], status.tolist(), times_ns.tolist()


def awkward_times(rng: np.random.Generator, n: int) -> np.ndarray:
    """Times of every size, exact ties of a nanosecond (k / 1024 s) and their neighbours."""
    ties = rng.integers(0, 10**9, n // 4) / 1024.0
    return np.concatenate(
        (
            [0.0, 1e-9, 5e-10, 0.0005, 2.5e-10, 7.4999999995, 1e-300, np.nextafter(TIME_LIMIT_S, 0)],
            ties,
            np.nextafter(ties, np.inf),
            np.nextafter(ties, 0),
            rng.integers(0, 10**9, n // 4) * 0.001,  # the runtime's grid
            rng.uniform(0, 1, n // 8) * 10.0 ** rng.integers(-9, 6, n // 8),
        )
    )


def test_time_text_is_python_percent_9f() -> None:
    times = awkward_times(np.random.default_rng(5), 40_000)
    rows = np.zeros((len(times), STATE_WIDTH))
    texts, status, times_ns = render(rows, times, np.zeros((len(times), 2), dtype=np.int64))
    assert set(status) == {STATE_WRITTEN}
    for t, text, t_ns in zip(times.tolist(), texts, times_ns, strict=True):
        assert text.startswith(b'{"t":%s,' % (b"%.9f" % t)), t
        assert t_ns == round(t * 1e9)
    assert time_nanoseconds(1 / 1024) == 976_562  # an exact tie: half to even


def test_state_text_is_python_percent_formatting_of_the_template() -> None:
    rng = np.random.default_rng(3)
    n = 400
    rows = awkward_values(rng, n * STATE_WIDTH).reshape(n, STATE_WIDTH)
    times = np.concatenate(([0.0, 1e-9, 0.0005, 2.5e-10, 7.4999999995], rng.uniform(0, 1e5, n - 5)))
    labels = rng.integers(0, 10**6, (n, 2)).astype(np.int64)
    texts, status, times_ns = render(rows, times, labels)
    assert set(status) == {STATE_WRITTEN}
    for i in range(n):
        micro = np.rint(rows[i] * 1e6).astype(np.int64).tolist()
        expected = STATE_FORMAT % (times[i], *micro, *labels[i].tolist())
        assert texts[i] == expected.encode()
        assert times_ns[i] == round(times[i] * 1e9)
    assert json.loads(texts[0])["q"][0] == pytest.approx(rows[0, 0], abs=5e-7)


def test_rows_with_a_non_finite_or_huge_value_or_odd_time_are_left_to_the_caller() -> None:
    rows = np.zeros((7, STATE_WIDTH))
    rows[1, 5], rows[2, 36], rows[3, 0] = np.nan, -np.inf, 1e12
    times = np.array([0.0, 1.0, 2.0, 3.0, -0.0, -1e-3, TIME_LIMIT_S])
    texts, status, _ = render(rows, times, np.zeros((7, 2), dtype=np.int64))
    assert status == [STATE_WRITTEN] + [STATE_NOT_EXACT] * 3 + [STATE_TIME_OUTSIDE] * 3
    assert texts[1:] == [b""] * 6
    assert json.loads(texts[0])["wrench"] == [0] * 6


def test_a_pose_sample_with_a_non_finite_or_huge_value_is_not_staged() -> None:
    poses = np.full((2, 2, 7), -1, dtype=np.int64)
    times_ns = np.zeros(2, dtype=np.int64)
    rows = np.arange(2, dtype=np.int64)
    positions, quats = np.zeros((2, 3)), np.tile([1.0, 0, 0, 0], (2, 1))
    quats[1, 2] = np.nan
    assert not stage_transform(poses, times_ns, 0, 5, positions, quats, rows)
    quats[1, 2] = 1e9
    assert not stage_transform(poses, times_ns, 0, 5, positions, quats, rows)
    assert (poses == -1).all()
    with pytest.raises(ValueError, match="outside"):
        stage_transform(poses, times_ns, 0, 5, positions, quats, np.array([0, 2], dtype=np.int64))


def test_staging_copies_the_vectors_in_message_order_and_refuses_wrong_lengths() -> None:
    rows, times = np.zeros((2, STATE_WIDTH)), np.zeros(2)
    labels = np.zeros((2, 2), dtype=np.int64)
    sizes = [n for _, n in STATE_VECTORS]
    vectors = [np.arange(n, dtype=float) + 10 * k for k, n in enumerate(sizes)]
    stage_state(rows, times, labels, 1, 2.5, *vectors, 4, 9)
    assert rows[1].tolist() == np.concatenate(vectors).tolist()
    assert times[1] == 2.5 and labels[1].tolist() == [4, 9]
    with pytest.raises(ValueError, match="x must have 3"):
        stage_state(rows, times, labels, 0, 0.0, *vectors[:3], np.zeros(4), *vectors[4:], 0, 0)
    with pytest.raises(TypeError):  # only contiguous float64 arrays; RunLog.state converts others
        stage_state(rows, times, labels, 0, 0.0, [0.0] * 6, *vectors[1:], 0, 0)
    assert not rows[0].any()


def test_template_refuses_directives_other_than_d() -> None:
    assert Template.from_format("a%%b%dc").literals.tobytes() == b"a%bc"
    with pytest.raises(ValueError, match="only %d"):
        Template.from_format('{"t":%.9f}')
