"""The compiled parameter-level folding (cosmos.runtime.kernels.parameter) against its references.

Lambda and the folded servo matrices are checked against the pure-NumPy
operational-space maths of cosmos.osc (eq. 27-29, 34 and section 5's blended
inverse), on seeded random inputs and on the PUMA 560 model near its wrist
singularity; refold's packing and reference error against pose_error; the
wrist geometry, the mass matrix and ParameterLevel.evaluate against Pinocchio
itself. Tolerances are ~1e-9 relative.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest

from cosmos.osc.dynamics import (
    DEFAULT_POLICY,
    OperationalDynamics,
    SingularityPolicy,
    null_space_damping,
    operational_dynamics,
)
from cosmos.osc.force import Selection, selection
from cosmos.osc.orientation import pose_error, so3_exp, so3_log
from cosmos.osc.unified import ForceGains, servo_matrices
from cosmos.robot_model import build_robot_model
from cosmos.runtime.kernels import evaluation as ek
from cosmos.runtime.kernels import parameter as pk
from cosmos.runtime.kernels import servo as sk
from cosmos.runtime.parameters import ParameterLevel
from cosmos.workcell import TOOL

RTOL = 1e-9
ROBOT = build_robot_model()
DEG = math.pi / 180.0
POLICY = DEFAULT_POLICY
SCALE = np.array((1.0, 1.0, 1.0, POLICY.length_scale_m, POLICY.length_scale_m, POLICY.length_scale_m))


def assert_close(actual: np.ndarray, expected: np.ndarray, rtol: float = RTOL) -> None:
    """Elementwise within ``rtol`` of the largest entry of ``expected`` (entries near zero included)."""
    scale = float(np.max(np.abs(expected)))
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * max(scale, 1e-12))


def kernel_lambda(lambda_inv: np.ndarray, policy: SingularityPolicy = POLICY) -> np.ndarray:
    return pk.lambda_from_inverse(
        lambda_inv, policy.max_effective_mass_kg, policy.blend_width, policy.length_scale_m
    )


def reference_dynamics(inertia: np.ndarray, jacobian: np.ndarray) -> OperationalDynamics:
    zeros = np.zeros(6)
    return operational_dynamics(inertia, jacobian, zeros, zeros, zeros, inertia_inv=np.linalg.inv(inertia))


def random_spd(rng: np.random.Generator) -> np.ndarray:
    m = rng.normal(size=(6, 6))
    return 0.3 * (m @ m.T) + np.diag(rng.uniform(0.5, 3.0, 6))  # (6, 6), [kg m^2]


def wrist_configuration(q5_rad: float) -> np.ndarray:
    """A PUMA pose with the tool pointing down whose wrist is ``q5_rad`` from its singularity."""
    q2, q4 = 30.0 * DEG, 0.0
    q3 = -math.pi - q2 - q5_rad  # keeps q2 + q3 + q5 = -pi
    return np.array((0.1, q2, q3, q4, q5_rad, 0.3))


def puma_arrays(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(A, A^-1, J)`` at ``q`` from Pinocchio: J of the tool point, world-aligned. # (6, 6) each."""
    model, data = ROBOT.model, ROBOT.model.createData()
    inertia = pin.crba(model, data, q)
    inertia = np.triu(inertia) + np.triu(inertia, 1).T
    jacobian = pin.computeFrameJacobian(model, data, q, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)
    return inertia, np.linalg.inv(inertia), jacobian.copy()


def effective_masses(lambda_: np.ndarray) -> np.ndarray:
    """Eigenvalues of the row-scaled Lambda (rotations as masses at the length scale), [kg]."""
    return np.linalg.eigvalsh(lambda_ / np.outer(SCALE, SCALE))


# --- lambda_from_inverse ----------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(4))
def test_lambda_is_the_plain_inverse_far_from_singularities(seed: int) -> None:
    """Eq. 27 in section 5's exact zone. Catches a wrong trace scaling that sends a regular
    configuration through the blend (a slightly wrong Lambda), or an inverse that is not one."""
    rng = np.random.default_rng(seed)
    inertia = random_spd(rng)
    jacobian = 0.6 * np.eye(6) + rng.normal(0.0, 0.1, (6, 6))
    reference = reference_dynamics(inertia, jacobian)
    assert reference.eigenvectors.shape[1] == 0, "want the exact regime"
    got = kernel_lambda(reference.lambda_inv)
    assert_close(got, reference.lambda_)
    assert_close(got @ reference.lambda_inv, np.eye(6))


def test_lambda_blends_out_constructed_singular_directions() -> None:
    """Section 5 on a Lambda^-1 built from chosen effective masses: one far past the threshold
    (dropped), one inside the blend band (smoothstep weight), the rest exact. Catches a weight
    without the smoothstep, the row scale applied once instead of on both sides, s_lo taken as
    the upper end of the band, or eigenvectors used as rows."""
    rng = np.random.default_rng(40)
    s_lo = 1.0 / POLICY.max_effective_mass_kg
    inverse_masses = np.array((1e-3 * s_lo, (1.0 + 0.4 * POLICY.blend_width) * s_lo, 0.01, 0.1, 1.0, 3.0))
    directions, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    # Lambda^-1 = J J^T with A = I, so the reference sees the same Lambda^-1 through eq. 27.
    jacobian = (directions * np.sqrt(inverse_masses)) / SCALE[:, None]
    reference = reference_dynamics(np.eye(6), jacobian)
    assert reference.blend.min() == 0.0 and 0.0 < np.sort(reference.blend)[1] < 1.0
    got = kernel_lambda(reference.lambda_inv)
    assert_close(got, reference.lambda_)
    assert effective_masses(got).max() <= POLICY.max_effective_mass_kg * (1.0 + 1e-9)


def test_lambda_blends_when_two_rows_of_j_are_nearly_dependent() -> None:
    """A Jacobian with two nearly parallel rows: one effective mass far above the threshold.
    Catches the exact-zone test passing a near-singular Lambda (a huge trace) through."""
    rng = np.random.default_rng(41)
    inertia = random_spd(rng)
    jacobian = 0.6 * np.eye(6) + rng.normal(0.0, 0.1, (6, 6))
    jacobian[4] = jacobian[1] + 1e-7 * rng.normal(size=6)
    reference = reference_dynamics(inertia, jacobian)
    assert reference.blend.min() == 0.0
    assert_close(kernel_lambda(reference.lambda_inv), reference.lambda_)


PUMA_WRIST_REGIMES = {  # q5 [deg] -> the blend weight of the heaviest direction it gives
    "at the singularity": (0.0, "dropped"),
    "dropped": (0.5, "dropped"),
    "inside the blend band": (1.9, "band"),
    "exact (trace test)": (3.0, "exact"),
}


@pytest.mark.parametrize("name", list(PUMA_WRIST_REGIMES))
def test_lambda_near_the_puma_wrist_singularity(name: str) -> None:
    """The PUMA 560 (Pinocchio model) as q5 -> 0: exactly at the singularity, a direction past the
    threshold (dropped), one inside the blend band (smoothstep weight ~0.4) and just far enough to
    pass the trace test. Catches the faults above on the arm's own, badly scaled, Lambda^-1
    (rotations in kg m^2), and a trace test that lets a near-singular Lambda through."""
    q5_deg, regime = PUMA_WRIST_REGIMES[name]
    inertia, inertia_inv, jacobian = puma_arrays(wrist_configuration(q5_deg * DEG))
    zeros = np.zeros(6)
    reference = operational_dynamics(inertia, jacobian, zeros, zeros, zeros, inertia_inv=inertia_inv)
    heaviest = reference.blend.min()
    if regime == "dropped":
        assert heaviest == 0.0
    elif regime == "band":
        assert 0.1 < heaviest < 0.9
    else:
        assert reference.eigenvectors.shape[1] == 0
    got = kernel_lambda(reference.lambda_inv)
    assert_close(got, reference.lambda_)
    assert effective_masses(got).max() <= POLICY.max_effective_mass_kg * (1.0 + 1e-9)


@pytest.mark.parametrize("kind", ["zero row", "repeated row", "diagonal with a zero"])
def test_lambda_of_a_singular_inverse(kind: str) -> None:
    """Lambda^-1 exactly singular (a zero row of J: np.linalg.inv refuses it) or singular but for
    rounding (a repeated row: the inverse "succeeds" with entries ~1e16), or with an eigenvalue
    exactly 0 (a diagonal Lambda^-1). Catches an uncaught LinAlgError in the compiled code, a
    rounding-noise inverse accepted as exact, a 0/0 weight, or an inf/nan Lambda reaching the servo."""
    rng = np.random.default_rng(42)
    inertia = random_spd(rng)
    jacobian = 0.6 * np.eye(6) + rng.normal(0.0, 0.1, (6, 6))
    if kind == "repeated row":
        jacobian[5] = jacobian[2]
    elif kind == "zero row":
        jacobian[3] = 0.0
    else:
        inertia, jacobian = np.eye(6), np.diag((0.5, 0.7, 0.0, 0.9, 1.1, 0.6))
    reference = reference_dynamics(inertia, jacobian)
    if kind != "repeated row":
        with pytest.raises(np.linalg.LinAlgError):
            np.linalg.inv(reference.lambda_inv)
    else:
        assert np.linalg.cond(reference.lambda_inv) > 1e14
    assert reference.blend.min() == 0.0
    got = kernel_lambda(reference.lambda_inv)
    assert np.all(np.isfinite(got))
    assert_close(got, reference.lambda_)


# --- fold_servo --------------------------------------------------------------------------------

FOLD_CASES = {
    "random arm, exact": (None, (True, False, True, True, False, True)),
    "random arm, one force axis": (None, (False, True, True, True, True, True)),
    "PUMA near the wrist singularity": (
        wrist_configuration(1.0 * DEG),
        (True, True, False, False, True, True),
    ),
    "PUMA, a general pose": (
        np.array((0.0, 0.8, -3.0, 0.2, -0.7, 3.0)),
        (True, True, False, True, True, True),
    ),
}


K_VF, XI_Q, LOOKAHEAD_S = 30.0, 20.0, 0.02


@dataclass(frozen=True)
class FoldInputs:
    inertia: np.ndarray
    inertia_inv: np.ndarray
    jacobian: np.ndarray
    bias: np.ndarray
    gravity: np.ndarray
    jdot_qdot: np.ndarray
    held: np.ndarray
    selection: Selection
    viscous: np.ndarray


def _fold_inputs(name: str) -> FoldInputs:
    q, motion_axes = FOLD_CASES[name]
    rng = np.random.default_rng(sorted(FOLD_CASES).index(name) + 50)
    if q is None:
        inertia = random_spd(rng)
        inertia_inv = np.linalg.inv(inertia)
        jacobian = 0.6 * np.eye(6) + rng.normal(0.0, 0.1, (6, 6))
    else:
        inertia, inertia_inv, jacobian = puma_arrays(q)
    return FoldInputs(
        inertia,
        inertia_inv,
        jacobian,
        bias=rng.normal(0.0, 2.0, 6),
        gravity=rng.normal(0.0, 20.0, 6),
        jdot_qdot=rng.normal(0.0, 0.5, 6),
        held=rng.normal(0.0, 1.0, 6),
        selection=selection(motion_axes, so3_exp(rng.uniform(-2.0, 2.0, 3))),
        viscous=rng.uniform(0.5, 5.0, 6),
    )


def _expected_fold(inputs: FoldInputs) -> dict[str, np.ndarray]:
    """The folded blocks from operational_dynamics, servo_matrices and null_space_damping."""
    dyn = operational_dynamics(
        inputs.inertia,
        inputs.jacobian,
        inputs.bias,
        inputs.gravity,
        inputs.jdot_qdot,
        inertia_inv=inputs.inertia_inv,
    )
    sel = inputs.selection
    servo = servo_matrices(dyn, sel, ForceGains(k_vf=K_VF))
    damping = np.column_stack([null_space_damping(dyn, inputs.inertia, e, XI_Q) for e in np.eye(6)])
    return {
        "J^T Lambda Omega": servo.motion_to_torque,
        "J^T Omega_bar": servo.force_to_torque,
        "-k_vf J^T Omega_bar Lambda Omega_bar": -servo.damping_to_torque,
        "b + g - J^T Lambda h + held": servo.bias_torque + inputs.held,
        "-xi_q (A - J^T Lambda J) + diag(viscous)": damping + np.diag(inputs.viscous),
        "Lambda^-1 Omega_bar": dyn.lambda_inv @ sel.omega_bar,
        "lookahead Jbar": LOOKAHEAD_S * dyn.jbar @ dyn.task_projection,
        "blend": dyn.blend,
        "projection": dyn.task_projection,
        "N^T": dyn.null_space_t,
    }


def _assert_fold(
    stacked: np.ndarray, force_to_acceleration: np.ndarray, jbar_lookahead: np.ndarray, inputs: FoldInputs
) -> None:
    expected = _expected_fold(inputs)
    got = {
        "J^T Lambda Omega": stacked[:, 0:6],
        "J^T Omega_bar": stacked[:, 6:12],
        "-k_vf J^T Omega_bar Lambda Omega_bar": stacked[:, 12:18],
        "b + g - J^T Lambda h + held": stacked[:, 18],
        "-xi_q (A - J^T Lambda J) + diag(viscous)": stacked[:, 19:25],
        "Lambda^-1 Omega_bar": force_to_acceleration,
        "lookahead Jbar": jbar_lookahead,
    }
    for block, actual in got.items():
        try:
            assert_close(actual, expected[block])
        except AssertionError as failure:
            raise AssertionError(f"block {block} differs") from failure


@pytest.mark.parametrize("name", list(FOLD_CASES))
def test_fold_servo_matches_eq_27_29_34(name: str) -> None:
    """Every block of the folded (6, 25) matrix, Lambda^-1 Omega_bar and the look-ahead Jbar,
    against operational_dynamics + servo_matrices + null_space_damping, with mixed motion/force
    axes in a rotated task frame. Catches Omega and Omega_bar swapped, a missing transpose,
    k_vf's sign, h or the held torque left out of column 18, the null-space damping as
    ``A - J^T Lambda J`` transposed or unscaled, viscous friction off the diagonal, Jbar
    computed with Lambda^-1, and a block left unwritten."""
    inputs = _fold_inputs(name)
    if name.startswith("PUMA near"):
        assert _expected_fold(inputs)["blend"].min() < 1.0, "want the blended regime"
    sel = inputs.selection
    stacked = np.full((6, 25), np.nan)
    force_to_acceleration = np.full((6, 6), np.nan)
    jbar_lookahead = np.full((6, 6), np.nan)
    projection = np.full((6, 6), np.nan)
    null_space_t = np.full((6, 6), np.nan)
    pk.fold_servo(
        inputs.inertia,
        inputs.inertia_inv,
        inputs.jacobian,
        inputs.jacobian,
        inputs.bias,
        inputs.gravity,
        inputs.jdot_qdot,
        inputs.held,
        sel.omega,
        sel.omega_bar,
        K_VF,
        XI_Q,
        inputs.viscous,
        LOOKAHEAD_S,
        POLICY.max_effective_mass_kg,
        POLICY.blend_width,
        POLICY.length_scale_m,
        stacked,
        force_to_acceleration,
        jbar_lookahead,
        projection,
        np.eye(6),
        null_space_t,
    )
    _assert_fold(stacked, force_to_acceleration, jbar_lookahead, inputs)
    assert_close(projection, _expected_fold(inputs)["projection"])
    # N^T is dimensionless and zero for a full task away from singularities: absolute tolerance.
    np.testing.assert_allclose(null_space_t, _expected_fold(inputs)["N^T"], atol=1e-8)


def test_refold_packs_the_servo_blocks() -> None:
    """refold (what ServoLevel calls) on the PUMA near its wrist singularity: the fold with its
    ``constants`` in the documented order, the evaluation copied into the kernel's slots, and the
    reference error ``(p - p_d, log(R R_d^T))`` of eq. 19/21 against pose_error. Catches swapped
    constants (k_vf for xi_q), a wrong slot index, or the error's rotation taken as R_d R^T."""
    inputs = _fold_inputs("PUMA near the wrist singularity")
    rng = np.random.default_rng(90)
    sel = inputs.selection
    evaluation_q = rng.uniform(-1.0, 1.0, 6)
    position, goal_position = rng.normal(0.0, 0.5, 3), rng.normal(0.0, 0.5, 3)
    rotation_tool, goal_rotation = so3_exp(rng.normal(size=3)), so3_exp(rng.normal(size=3))
    rotation_sensor = so3_exp(rng.normal(size=3))
    to_tool, to_com = rng.normal(0.0, 0.2, 3), rng.normal(0.0, 0.1, 3)
    constants = np.array(
        (K_VF, XI_Q, LOOKAHEAD_S, POLICY.max_effective_mass_kg, POLICY.blend_width, POLICY.length_scale_m)
    )
    sentinel = 1234.5  # in the slots refold must leave alone
    stacked = np.full((6, 25), np.nan)
    vectors = np.full((sk.VECTORS, 6), sentinel)
    matrices = np.full((sk.MATRICES, 6, 6), sentinel)
    jacobian, jbar_lookahead = np.full((6, 6), sentinel), np.full((6, 6), sentinel)
    values = np.full(ek.size(6), np.nan)
    for offset, array in (
        (ek.Q, evaluation_q),
        (ek.POSITION, position),
        (ek.ROTATION_TOOL, rotation_tool),
        (ek.ROTATION_SENSOR, rotation_sensor),
        (ek.SENSOR_TO_TOOL, to_tool),
        (ek.SENSOR_TO_COM, to_com),
        (ek.jacobian_at(6), inputs.jacobian),
        (ek.inertia_at(6), inputs.inertia),
        (ek.inertia_inv_at(6), inputs.inertia_inv),
        (ek.gravity_at(6), inputs.gravity),
        (ek.bias_at(6), inputs.bias),
        (ek.JDOT_QDOT, inputs.jdot_qdot),
    ):
        values[offset : offset + array.size] = array.ravel()
    pk.refold(
        values,
        inputs.held,
        sel.omega,
        sel.omega_bar,
        goal_position,
        goal_rotation,
        constants,
        inputs.viscous,
        stacked,
        vectors,
        matrices,
        jacobian,
        jbar_lookahead,
        np.full((6, 6), sentinel),
    )
    _assert_fold(stacked, matrices[sk.FORCE_TO_ACCELERATION], jbar_lookahead, inputs)
    assert np.array_equal(jacobian, inputs.jacobian)
    assert np.array_equal(matrices[sk.OMEGA_BAR], sel.omega_bar)
    assert np.array_equal(matrices[sk.ROTATION_SENSOR, :3, :3], rotation_sensor)
    assert np.array_equal(vectors[sk.EVALUATION_Q], evaluation_q)
    assert np.array_equal(vectors[sk.GRAVITY], inputs.gravity)
    assert np.array_equal(vectors[sk.SENSOR_OFFSETS], np.concatenate((to_tool, to_com)))
    assert_close(
        vectors[sk.REFERENCE_ERROR], pose_error(position, rotation_tool, goal_position, goal_rotation)
    )
    for row in (sk.KP, sk.KV, sk.FORCE_WORLD, sk.FORCE_START, sk.REFERENCE_VELOCITY, sk.COULOMB_NM):
        assert np.all(vectors[row] == sentinel), f"refold wrote vectors row {row}"
    assert np.all(matrices[sk.ROTATION_TASK] == sentinel)


# --- symmetric_from_upper ----------------------------------------------------------------------


def test_symmetric_from_upper_ignores_the_lower_triangle() -> None:
    """Catches the lower triangle copied instead of the upper (Pinocchio leaves it stale)."""
    rng = np.random.default_rng(60)
    upper = rng.normal(size=(6, 6))
    full = ek.symmetric_from_upper(upper)
    assert np.array_equal(full, np.triu(upper) + np.triu(upper, 1).T)


def test_symmetric_from_upper_rebuilds_pinocchios_mass_matrix() -> None:
    """On computeAllTerms' A and computeMinverse's A^-1 (upper triangles): A a equals
    rnea(q, 0, a) - g(q) and A^-1 A = I. Catches a transposed or half-filled A reaching Lambda."""
    rng = np.random.default_rng(61)
    model, data = ROBOT.model, ROBOT.model.createData()
    for _ in range(3):
        q = rng.uniform(ROBOT.q_lower_rad, ROBOT.q_upper_rad)
        pin.computeAllTerms(model, data, q, np.zeros(6))
        inertia = ek.symmetric_from_upper(data.M.copy())
        inertia_inv = ek.symmetric_from_upper(pin.computeMinverse(model, data, q).copy())
        gravity = pin.computeGeneralizedGravity(model, data, q).copy()
        for a in np.eye(6):
            expected = pin.rnea(model, data, q, np.zeros(6), a) - gravity
            assert_close(inertia @ a, expected)
        assert_close(inertia_inv @ inertia, np.eye(6))


# --- the evaluation from computeAllTerms --------------------------------------------------------


def _frames_at(q: np.ndarray) -> tuple[pin.SE3, pin.SE3, pin.SE3]:
    """World placements of the flange, the wrist sensor and the tool point at ``q``."""
    model, data = ROBOT.model, ROBOT.model.createData()
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    return (
        data.oMf[ROBOT.flange_frame].copy(),
        data.oMf[ROBOT.sensor_frame].copy(),
        data.oMf[ROBOT.tool_frame].copy(),
    )


def _expected_wrist(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sensor orientation, sensor-to-tool and sensor-to-centre-of-mass in world, from oMf and TOOL."""
    flange, sensor, tool = _frames_at(q)
    com_world = flange.act(np.asarray(TOOL.com_in_flange))
    return sensor.rotation, tool.translation - sensor.translation, com_world - sensor.translation


def test_parameter_level_evaluation_matches_pinocchio() -> None:
    """ParameterLevel.evaluate end to end (its constants and evaluation_values from computeAllTerms'
    arrays) against Pinocchio's own frame, Jacobian, gravity, dynamics and classical-acceleration
    functions. Catches the Jacobian taken at the wrist instead of the tool point, g with the wrong
    sign or mass, the centre of mass taken from the flange instead of the sensor, the offsets' sign,
    flange axes mistaken for tool axes, b = nle - g or h = Jdot qd (eq. 12, 14) formed wrongly
    (h without the w x v_p term), a half-filled A or a wrong A^-1, and a wrong limit margin."""
    rng = np.random.default_rng(71)
    level = ParameterLevel(ROBOT)
    model, data = ROBOT.model, ROBOT.model.createData()
    for _ in range(6):
        q, qd = rng.uniform(ROBOT.q_lower_rad, ROBOT.q_upper_rad), rng.normal(0.0, 0.5, 6)
        evaluation = level.evaluate(q, qd)
        assert np.array_equal(evaluation.q, q)
        rotation, to_tool, to_com = _expected_wrist(q)
        assert_close(evaluation.rotation_sensor_to_world, rotation)
        assert_close(evaluation.sensor_to_tool_m, to_tool)
        assert_close(evaluation.sensor_to_com_m, to_com)
        tool = _frames_at(q)[2]
        assert_close(evaluation.position, tool.translation)
        assert_close(evaluation.rotation_tool_to_world, tool.rotation)
        jacobian = pin.computeFrameJacobian(model, data, q, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)
        assert_close(evaluation.jacobian, jacobian)

        gravity = pin.computeGeneralizedGravity(model, data, q).copy()
        assert_close(evaluation.gravity, gravity)
        assert_close(evaluation.bias, pin.nonLinearEffects(model, data, q, qd) - gravity)
        inertia = pin.crba(model, data, q)
        assert_close(evaluation.inertia, np.triu(inertia) + np.triu(inertia, 1).T)
        assert_close(evaluation.inertia_inv @ evaluation.inertia, np.eye(6))
        assert np.array_equal(evaluation.inertia_inv, evaluation.inertia_inv.T)
        pin.forwardKinematics(model, data, q, qd, np.zeros(6))
        pin.updateFramePlacements(model, data)
        accel = pin.getFrameClassicalAcceleration(model, data, ROBOT.tool_frame, pin.LOCAL_WORLD_ALIGNED)
        assert_close(evaluation.jdot_qdot, np.concatenate((accel.linear, accel.angular)))
        margin = min(np.min(q - ROBOT.q_lower_rad), np.min(ROBOT.q_upper_rad - q))
        assert evaluation.values[ek.LIMIT_MARGIN] == pytest.approx(margin, abs=1e-15)
        assert not evaluation.values.flags.writeable


def test_spd_inverse_matches_numpy() -> None:
    """The Cholesky inverse against numpy's LU one on random SPD matrices, condition up to ~1e6.
    Catches a wrong index in either triangular pass (the product would not be symmetric or not I)."""
    rng = np.random.default_rng(72)
    for scale in (1.0, 1e-3, 1e3):
        a = random_spd(rng) * np.outer(np.geomspace(1.0, scale, 6), np.geomspace(1.0, scale, 6))
        out = np.empty((6, 6))
        ek.spd_inverse_into(out, a)
        assert_close(out, np.linalg.inv(a), rtol=1e-7)


# --- rotation_log ------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.0, 3e-5, 0.7, 2.5, math.pi - 3e-3, math.pi])
def test_rotation_log_matches_so3_log(angle: float) -> None:
    """The reference error's log (refold) against cosmos.osc.orientation.so3_log, including the small
    angle series and the near-pi branch. Catches a flipped axis sign near pi."""
    rng = np.random.default_rng(80)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    rotation = so3_exp(angle * axis)
    got, expected = pk.rotation_log(rotation), so3_log(rotation)
    if angle == math.pi:  # the sign of the axis is arbitrary at pi: both are the same rotation
        assert_close(so3_exp(got), rotation)
    else:
        assert_close(got, expected, rtol=1e-9 if angle > 1e-3 else 1e-7)
        assert_close(so3_exp(got), rotation)


@pytest.mark.parametrize("q", [np.array((0.0, 0.8, -3.0, 0.2, -0.7, 3.0)), wrist_configuration(1.0 * DEG)])
def test_fold_servo_orientation_free_is_the_position_task_of_eq_27_28(q: np.ndarray) -> None:
    """ORIENTATION FREE (rotation rows neither motion nor force) folds Lambda_r, Jbar and N^T of
    the 3-row position task, computed apart by operational_dynamics on J[:3] (eq. 27-28). Catches
    the free rows left in Lambda (an empty null space: eq. 34 inert), Lambda_r taken as the
    position block of the 6-row Lambda (not dynamically consistent: N^T moves the tool), and N^T
    not written."""
    inertia, inertia_inv, jacobian = puma_arrays(q)
    zero = np.zeros(6)
    omega = np.diag((1.0, 1.0, 1.0, 0.0, 0.0, 0.0))
    stacked, null_space_t = np.zeros((6, 25)), np.full((6, 6), np.nan)
    out = [np.zeros((6, 6)) for _ in range(3)]
    pk.fold_servo(
        inertia, inertia_inv, jacobian, jacobian, zero, zero, zero, zero, omega, np.zeros((6, 6)),
        K_VF, XI_Q, zero, LOOKAHEAD_S, POLICY.max_effective_mass_kg, POLICY.blend_width,
        POLICY.length_scale_m, stacked, *out, np.eye(6), null_space_t,
    )  # fmt: skip
    position = operational_dynamics(inertia, jacobian[:3], zero, zero, zero[:3], inertia_inv=inertia_inv)
    np.testing.assert_allclose(null_space_t, position.null_space_t, atol=1e-8)
    assert_close(stacked[:, 0:3], jacobian[:3].T @ position.lambda_)
    assert_close(stacked[:, 3:6], np.zeros((6, 3)))
    damping = np.column_stack([null_space_damping(position, inertia, e, XI_Q) for e in np.eye(6)])
    assert_close(stacked[:, 19:25], damping)
    assert np.trace(null_space_t) == pytest.approx(3.0, abs=1e-9)
