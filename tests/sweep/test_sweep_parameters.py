"""--vary parsing with the language's units, and each run's draws from the seed and its index."""

import math

import numpy as np
import pytest

from cosmos.errors import UsageError
from cosmos.sweep.parameters import Kind, draw, noise_seed, parse_varies, parse_vary


@pytest.mark.parametrize(
    ("text", "kind", "a", "b"),
    [
        ("hole.x=normal(0,1mm)", Kind.NORMAL, 0.0, 1e-3),
        ("hole.y=uniform(-2 mm, 2mm)", Kind.UNIFORM, -2e-3, 2e-3),
        ("slope.rz=0.5 deg", Kind.CONSTANT, math.pi / 360, 0.0),
        ("table.z=-1.5cm", Kind.CONSTANT, -0.015, 0.0),
        ("friction=uniform(0.2, 0.6)", Kind.UNIFORM, 0.2, 0.6),
        ("bias.fz=normal(0.5 N, 0.1 N)", Kind.NORMAL, 0.5, 0.1),
        ("bias.tx=2 Nm", Kind.CONSTANT, 2.0, 0.0),
        ("payload=0.25", Kind.CONSTANT, 0.25, 0.0),
        ("hole.x=0.001", Kind.CONSTANT, 0.001, 0.0),
    ],
)
def test_values_take_the_language_units(text: str, kind: Kind, a: float, b: float) -> None:
    """Catches a second unit table drifting from the language's (mm, cm, deg, Nm) or a bare number not SI."""
    vary = parse_vary(text)
    assert vary.kind is kind
    assert vary.a == pytest.approx(a, abs=1e-15)
    assert vary.b == pytest.approx(b, abs=1e-15)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("hole.q=1mm", "unknown parameter 'hole.q'"),
        ("hole.x=1 N", "hole.x is in mm; 'N' is not a unit of that kind"),
        ("hole.x=1 mmm", "unknown unit 'mmm'"),
        ("hole.x=normal(0)", "normal() takes two values"),
        ("hole.x=normal(0, -1mm)", "standard deviation must be >= 0"),
        ("hole.x=uniform(2mm, 1mm)", "needs lo <= hi"),
        ("payload=1 kg", "bare number in kg"),
        ("seed=normal(0, 1)", "the noise seed is a constant"),
        ("hole.x", "expected NAME=DIST"),
        ("hole.x=abc", "is not a number with a unit"),
        # A model error past 1 drew a negative link mass: MuJoCo's traceback, and no log.
        ("model_error=80", "model_error must be from 0 to 0.5"),
        ("model_error=uniform(0.3, 2)", "model_error must be from 0 to 0.5"),
        # 1e400 was taken as infinity and written to the results as the non-JSON `Infinity`.
        ("friction=1e400", "'1e400' is not a finite number"),
        ("friction=-0.2", "friction must be at least 0"),
        ("payload=uniform(-1, 1)", "payload must be at least 0 kg"),
    ],
)
def test_mistakes_are_usage_errors_that_say_what_is_wrong(text: str, message: str) -> None:
    """Catches a bad --vary running a sweep with a wrong world instead of stopping with a clear message."""
    with pytest.raises(UsageError, match=None) as caught:
        parse_vary(text)
    assert message in str(caught.value)
    assert str(caught.value).startswith(f"--vary {text}: ")


def test_a_parameter_given_twice_is_an_error() -> None:
    """Catches the second --vary silently replacing the first."""
    with pytest.raises(UsageError, match="hole.x given more than once"):
        parse_varies(["hole.x=1mm", "hole.x=2mm"])


def test_a_run_s_draws_depend_on_the_seed_and_its_index_only() -> None:
    """Catches draws that depend on the order of the runs or on the other parameters varied."""
    x = parse_vary("hole.x=normal(0, 1mm)")
    friction = parse_vary("friction=uniform(0.2, 0.6)")
    alone = draw((x,), 7, 12)
    together = draw((friction, x), 7, 12)
    assert alone["hole.x"] == together["hole.x"]
    assert draw((x,), 7, 12) == alone
    assert draw((x,), 7, 13)["hole.x"] != alone["hole.x"]
    assert draw((x,), 8, 12)["hole.x"] != alone["hole.x"]


def test_noise_seed_is_the_index_th_child_of_the_sweep_s_seed_sequence() -> None:
    """Catches a run's noise seed that is not the i-th child of SeedSequence(seed).spawn (numpy's own)."""
    children = np.random.SeedSequence(42).spawn(5)
    for index, child in enumerate(children):
        assert noise_seed(42, index) == int(child.generate_state(1, np.uint32)[0])
    assert draw((), 42, 3)["seed"] == noise_seed(42, 3)
    assert draw((parse_vary("seed=9"),), 42, 3)["seed"] == 9


def test_draws_have_the_distribution_asked() -> None:
    """Catches sd taken as variance, uniform bounds swapped or a clipped range (4-sigma bounds, n = 4000)."""
    n = 4000
    normal = parse_vary("hole.x=normal(1mm, 2mm)")
    values = np.array([normal.draw(3, i) for i in range(n)])
    assert abs(values.mean() - 1e-3) < 4 * 2e-3 / math.sqrt(n)
    assert values.std() == pytest.approx(2e-3, rel=0.05)
    uniform = parse_vary("hole.y=uniform(-2mm, 2mm)")
    values = np.array([uniform.draw(3, i) for i in range(n)])
    assert values.min() >= -2e-3 and values.max() <= 2e-3
    assert abs(values.mean()) < 4 * (4e-3 / math.sqrt(12)) / math.sqrt(n)
    friction = parse_vary("friction=normal(0.05, 0.1)")
    assert min(friction.draw(3, i) for i in range(200)) == 0.0  # clipped at its minimum


def test_canonical_text_parses_back_to_the_same_distribution() -> None:
    """Catches a results file whose recorded --vary does not redraw the same runs (--sample)."""
    for text in ("hole.x=normal(0,1mm)", "slope.ry=uniform(-1deg, 2 deg)", "bias.tz=0.01 Nm", "payload=0.3"):
        vary = parse_vary(text)
        assert parse_vary(vary.text()) == vary


def test_normal_draws_are_clipped_to_the_range() -> None:
    """Catches a normal model error drawn past its range (a negative friction factor in the plant)."""
    vary = parse_vary("model_error=normal(0.4, 1)")
    values = [vary.draw(3, index) for index in range(200)]
    assert min(values) == 0.0 and max(values) == 0.5
