"""docs/workcell.md against the MuJoCo model: every number in the doc is read back from the model.

Each row of the doc's tables names a quantity; :data:`QUANTITIES` computes it
from the compiled scene at the home keyframe (geom sizes, world poses from
``mj_kinematics``, body masses). The doc's value must be the model's rounded to
the digits printed, every quantity must be in the doc, and the doc must hold no
number outside those value cells, so the doc and the model cannot drift apart.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np
import pytest

from cosmos.robots import PANDA
from cosmos.workcell import HOME_KEY, SCENE_XML

DOC = Path(__file__).resolve().parents[1] / "docs" / "workcell.md"
UNITS = {"mm": 1e-3, "m": 1.0, "deg": math.pi / 180, "kg": 1.0, "": 1.0}


class Scene:
    """The compiled workcell at its home keyframe, with lookups by name."""

    def __init__(self, scene_xml: Path = SCENE_XML) -> None:
        self.model = mujoco.MjModel.from_xml_path(str(scene_xml))
        self.data = mujoco.MjData(self.model)
        key = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_KEY, HOME_KEY)
        mujoco.mj_resetDataKeyframe(self.model, self.data, key)
        mujoco.mj_kinematics(self.model, self.data)

    def geom(self, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(world position (3,), world rotation (3, 3), MuJoCo size (3,)) of a geom."""
        g = self.model.geom(name).id
        return (
            self.data.geom_xpos[g].copy(),
            self.data.geom_xmat[g].reshape(3, 3).copy(),
            self.model.geom_size[g],
        )

    def geoms(self, prefix: str) -> list[str]:
        names = [self.model.geom(i).name for i in range(self.model.ngeom)]
        return [n for n in names if re.fullmatch(prefix + r"\d+", n)]

    def site(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        s = self.model.site(name).id
        return self.data.site_xpos[s].copy(), self.data.site_xmat[s].reshape(3, 3).copy()

    def along_tool(self, point: np.ndarray) -> float:
        """Distance of a world point from the flange along the flange's z axis [m]."""
        origin, rotation = self.site("flange")
        return float((point - origin) @ rotation[:, 2])


@functools.cache
def _panda() -> Scene:
    """The Panda's workcell at its home keyframe."""
    return Scene(PANDA.scene_xml)


def _box_top(s: Scene, name: str) -> float:
    position, _, size = s.geom(name)
    return float(position[2] + size[2])


def _extent(s: Scene, name: str, axis: int) -> np.ndarray:
    position, _, size = s.geom(name)
    return np.array([position[axis] - size[axis], position[axis] + size[axis]])


def _legs(s: Scene, axis: int) -> np.ndarray:
    return np.unique(np.round([s.geom(n)[0][axis] for n in s.geoms("table_leg")], 9))


def _radial(s: Scene, name: str) -> tuple[float, np.ndarray, np.ndarray]:
    """A hole box's (centre's distance from the hole axis, radial unit vector, world centre)."""
    axis_point, _ = s.site("hole")
    position, _, _ = s.geom(name)
    offset = position - axis_point
    offset[2] = 0.0
    return float(np.linalg.norm(offset)), offset / np.linalg.norm(offset), position


def _inner_radii(s: Scene, prefix: str) -> np.ndarray:
    """Distance from the hole axis to the inner face of each box ``prefix``NN [m]."""
    out = []
    for name in s.geoms(prefix):
        radius, _, _ = _radial(s, name)
        _, rotation, size = s.geom(name)
        assert abs(rotation[2, 0]) < 1e-9, f"{name}'s x axis must be horizontal"
        out.append(radius - size[0])
    return np.array(out)


def _one(values: np.ndarray) -> float:
    assert np.ptp(values) < 1e-9, f"the sectors differ: {values}"
    return float(values[0])


def _chamfer_face(s: Scene, name: str) -> tuple[np.ndarray, float, np.ndarray]:
    """The chamfer box's inner face: (outward unit normal, offset, box centre), ``n . (p - c) = offset``.

    Of the box's six faces, the one facing the hole's axis and up.
    """
    _, direction, centre = _radial(s, name)
    _, rotation, size = s.geom(name)
    faces = [(sign * rotation[:, k], size[k]) for k in range(3) for sign in (1.0, -1.0)]
    inner = [(n, offset) for n, offset in faces if n @ direction < -0.1 and n[2] > 0.1]
    assert len(inner) == 1, f"{name}: no single face looks up and into the hole"
    return inner[0][0], float(inner[0][1]), centre


def _chamfer_meets(s: Scene, name: str, height: float | None = None, radius: float | None = None) -> float:
    """In its sector's radial plane, the radius at which the chamfer face is at ``height`` (world z),
    or the height at which it is at ``radius`` [m]."""
    axis_point, _ = s.site("hole")
    _, direction, _ = _radial(s, name)
    normal, offset, centre = _chamfer_face(s, name)
    base = axis_point - centre
    if height is not None:
        base = base + np.array([0.0, 0.0, height - axis_point[2]])
        return float((offset - normal @ base) / (normal @ direction))
    assert radius is not None
    base = base + radius * direction
    return float(axis_point[2] + (offset - normal @ base) / normal[2])


def _chamfer(s: Scene) -> tuple[float, float]:
    """(depth below the mouth where the chamfer face meets the wall [m], its angle from the wall [rad])."""
    mouth_z = s.site("hole")[0][2]
    flats = _flats(s)
    depths, angles = [], []
    for name in s.geoms("hole_chamfer"):
        depths.append(mouth_z - _chamfer_meets(s, name, radius=flats))
        normal, _, _ = _chamfer_face(s, name)
        angles.append(math.asin(normal[2]))  # the normal leaves the horizontal as the face leaves the wall
    return _one(np.array(depths)), _one(np.array(angles))


def _flats(s: Scene) -> float:
    return _one(_inner_radii(s, "hole_wall"))


def _tool_cylinder(s: Scene, name: str) -> np.ndarray:
    position, rotation, size = s.geom(name)
    return np.array(
        [s.along_tool(position - size[1] * rotation[:, 2]), s.along_tool(position + size[1] * rotation[:, 2])]
    )


def _peg(s: Scene) -> np.ndarray:
    """(start of the peg's cylinder, its flat end) along the tool [m]: cylinder ``peg``, then the
    end disc ``peg_end`` inside the chamfer."""
    return np.array([_tool_cylinder(s, "peg").min(), _tool_cylinder(s, "peg_end").max()])


def _peg_chamfer_angle(s: Scene) -> float:
    """Angle of the peg's chamfer facets from the peg's axis [rad]: each facet box's face that
    looks away from the axis and towards the end."""
    angles = []
    flange = s.site("flange")[1][:, 2]
    for name in s.geoms("peg_chamfer"):
        position, rotation, size = s.geom(name)
        axis_point = s.site("tool")[0]
        radial = position - axis_point - ((position - axis_point) @ flange) * flange
        radial /= np.linalg.norm(radial)
        faces = [sign * rotation[:, k] for k in range(3) for sign in (1.0, -1.0)]
        outer = [n for n in faces if n @ radial > 0.1 and n @ flange > 0.1]
        assert len(outer) == 1, f"{name}: no single face looks out and towards the end"
        angles.append(math.pi / 2 - math.acos(float(outer[0] @ flange)))  # the face, not its normal
    return _one(np.round(np.array(angles), 12))


def _plate_face_centre(s: Scene) -> np.ndarray:
    position, rotation, size = s.geom("slope_plate")
    return position + size[2] * rotation[:, 2]


def _tool_point_home(s: Scene) -> np.ndarray:
    return s.site("tool")[0]


QUANTITIES: dict[str, Callable[[Scene], float | np.ndarray]] = {
    # floor and table
    "floor top": lambda s: _box_top(s, "floor"),
    "floor size": lambda s: 2 * s.geom("floor")[2][:2],
    "table top height": lambda s: _box_top(s, "table_top"),
    "table top thickness": lambda s: 2 * s.geom("table_top")[2][2],
    "table top x": lambda s: _extent(s, "table_top", 0),
    "table top y": lambda s: _extent(s, "table_top", 1),
    "table leg size": lambda s: _one_size(s, "table_leg"),
    "table leg centres x": lambda s: _legs(s, 0),
    "table leg centres y": lambda s: _legs(s, 1),
    "pedestal radius": lambda s: s.geom("pedestal")[2][0],
    "pedestal height": lambda s: 2 * s.geom("pedestal")[2][1],
    # hole fixture
    "hole mouth centre": lambda s: s.site("hole")[0],
    "hole sides": lambda s: float(len(s.geoms("hole_wall"))),
    "hole radius to the flats": _flats,
    "hole radius to the corners": lambda s: _flats(s) / math.cos(math.pi / len(s.geoms("hole_wall"))),
    "hole depth": lambda s: s.site("hole")[0][2] - _box_top(s, "hole_bottom"),
    "chamfer depth": lambda s: _chamfer(s)[0],
    "chamfer angle": lambda s: _chamfer(s)[1],
    "mouth radius": lambda s: _one(_inner_radii(s, "hole_top")),
    "mouth radius of the chamfer face": lambda s: _one(
        np.array([_chamfer_meets(s, n, height=s.site("hole")[0][2]) for n in s.geoms("hole_chamfer")])
    ),
    "fixture outer radius to the flats": lambda s: _one(_inner_radii(s, "hole_wall") + 2 * _wall_half_x(s)),
    "fixture height": lambda s: (
        s.site("hole")[0][2] - _one(np.array([_bottom(s, n) for n in s.geoms("hole_wall")]))
    ),
    # tilted plate
    "plate face size": lambda s: 2 * s.geom("slope_plate")[2][:2],
    "plate thickness": lambda s: 2 * s.geom("slope_plate")[2][2],
    "plate face centre": _plate_face_centre,
    "plate tilt": lambda s: math.acos(s.geom("slope_plate")[1][2, 2]),
    "plate face normal": lambda s: s.geom("slope_plate")[1][:, 2],
    # frames of the language
    "frame table origin": lambda s: s.site("table")[0],
    "frame table x axis": lambda s: s.site("table")[1][:, 0],
    "frame table z axis": lambda s: s.site("table")[1][:, 2],
    "frame hole origin": lambda s: s.site("hole")[0],
    "frame hole x axis": lambda s: s.site("hole")[1][:, 0],
    "frame hole z axis": lambda s: s.site("hole")[1][:, 2],
    "frame slope origin": lambda s: s.site("slope")[0],
    "frame slope x axis": lambda s: s.site("slope")[1][:, 0],
    "frame slope z axis": lambda s: s.site("slope")[1][:, 2],
    # tool
    "tool length": lambda s: s.along_tool(s.site("tool")[0]),
    "sensor measuring plane": lambda s: s.along_tool(s.site("ft_sensor")[0]),
    "sensor housing": lambda s: _tool_cylinder(s, "ft_sensor_housing"),
    "sensor housing radius": lambda s: s.geom("ft_sensor_housing")[2][0],
    "collar": lambda s: _tool_cylinder(s, "peg_collar"),
    "collar radius": lambda s: s.geom("peg_collar")[2][0],
    "peg": _peg,
    "peg radius": lambda s: s.geom("peg")[2][0],
    "peg end radius": lambda s: s.geom("peg_end")[2][0],
    "peg chamfer": lambda s: s.geom("peg")[2][0] - s.geom("peg_end")[2][0],
    "peg chamfer facets": lambda s: float(len(s.geoms("peg_chamfer"))),
    "peg chamfer angle": _peg_chamfer_angle,
    "peg length beyond the collar": lambda s: _peg(s)[1] - _tool_cylinder(s, "peg_collar")[1],
    "diametral clearance in the hole": lambda s: 2 * (_flats(s) - s.geom("peg")[2][0]),
    "tool mass": lambda s: float(s.model.body_mass[s.model.body("tool").id]),
    "tool point at home": _tool_point_home,
    "tool point at home above the table frame": lambda s: _tool_point_home(s)[2] - s.site("table")[0][2],
    # the Panda's scene: its own arm among the same fixtures (tests/test_panda_model.py)
    "Panda pedestal height": lambda s: 2 * _panda().geom("pedestal")[2][1],
    "Panda shoulder height": lambda s: _panda().data.xpos[_panda().model.body("link2").id][2],
    "Panda home": lambda s: _panda().model.key(HOME_KEY).qpos,
    "Panda tool point at home": lambda s: _tool_point_home(_panda()),
}


def _one_size(s: Scene, prefix: str) -> np.ndarray:
    sizes = np.array([2 * s.geom(n)[2] for n in s.geoms(prefix)])
    assert np.ptp(sizes, axis=0).max() < 1e-12
    return sizes[0]


def _wall_half_x(s: Scene) -> np.ndarray:
    return np.array([s.geom(n)[2][0] for n in s.geoms("hole_wall")])


def _bottom(s: Scene, name: str) -> float:
    position, _, size = s.geom(name)
    return float(position[2] - size[2])


def doc_rows() -> dict[str, str]:
    """``quantity -> value`` of every table row of docs/workcell.md whose value cell holds a number."""
    rows = {}
    for line in DOC.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
        if len(cells) >= 2 and re.search(r"\d", cells[1]):
            assert cells[0] not in rows, f"quantity '{cells[0]}' twice in the doc"
            rows[cells[0]] = cells[1]
    return rows


def parse_value(text: str) -> tuple[np.ndarray, np.ndarray, float]:
    """A value cell (``200 mm``, ``(600, -150, 200) mm``, ``20 deg``, ``16``) as SI numbers.

    Returns:
        (values, half of the last printed digit of each, the unit's scale).
    """
    match = re.fullmatch(r"\(?([-+0-9., ]+?)\)?\s*(mm|m|deg|kg|)", text)
    assert match, f"cannot read the value '{text}': write 'N unit' or '(a, b, c) unit'"
    numbers = [n.strip() for n in match.group(1).split(",")]
    scale = UNITS[match.group(2)]
    values = np.array([float(n) for n in numbers]) * scale
    digits = np.array([len(n.split(".")[1]) if "." in n else 0 for n in numbers])
    return values, 0.5 * 10.0**-digits * scale, scale


@pytest.fixture(scope="module")
def scene() -> Scene:
    return Scene()


def test_doc_lists_every_quantity_and_nothing_else() -> None:
    """Catches a row added to the doc without a check here, or a checked quantity dropped from the doc."""
    assert set(doc_rows()) == set(QUANTITIES)


@pytest.mark.parametrize("quantity", sorted(QUANTITIES))
def test_doc_value_is_the_model_rounded(scene: Scene, quantity: str) -> None:
    """Catches a workcell number in the doc that differs from the MuJoCo model (a fixture moved or
    resized in scene.xml and not in the doc, or a typo), beyond the rounding of its printed digits."""
    text = doc_rows()[quantity]
    documented, half_digit, scale = parse_value(text)
    model = np.atleast_1d(np.asarray(QUANTITIES[quantity](scene), dtype=float))
    assert model.shape == documented.shape, f"{quantity}: the doc gives {text}, the model {model / scale}"
    assert np.all(np.abs(model - documented) <= half_digit + 1e-9 * scale), (
        f"{quantity}: the doc says {text}, the model has {np.round(model / scale, 6)}"
    )


def test_doc_has_no_number_outside_its_checked_values() -> None:
    """Catches a number written in the doc's prose or notes, which no test would compare with the model."""
    for number, line in enumerate(DOC.read_text(encoding="utf-8").splitlines(), start=1):
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            line = " ".join([cells[0], *cells[2:]])
        prose = re.sub(r"`[^`]*`", "", line)
        assert not re.search(r"\d", prose), (
            f"docs/workcell.md:{number}: a number outside a value cell: {line}"
        )
