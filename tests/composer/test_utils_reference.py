"""Ours against dm_control's own `utils.rewards`, `utils.transformations` and
`utils.inverse_kinematics` (from the published wheel, fetched at test time, loaded under
another name): seeded random inputs and the special values (zeros of both signs, infinities,
NaN, denormals, poles) give the same values to the last bit, the same dtypes and shapes,
and the same errors."""

from __future__ import annotations

import importlib
import itertools
import logging
import sys
import warnings
import zipfile

import numpy as np
import pytest

import mjcf
from composer.utils import inverse_kinematics, rewards, transformations
from tests import dm_control_wheel

PACKAGE = "dm_control_utils_reference"  # dm_control's three modules, renamed
_IMPORTS = (  # their inverse kinematics reaches MuJoCo through dm_control's alias of it
    ("from dm_control.mujoco.wrapper import mjbindings", "import mujoco as _mujoco"),
    ("mjlib = mjbindings.mjlib", "mjlib = _mujoco"),
)
_ASSETS = "dm_control/mujoco/testing/assets/"


@pytest.fixture(scope="module")
def theirs(tmp_path_factory):
    """A namespace of dm_control's modules (theirs.rewards ...) and test models
    (theirs.models['arm.xml'] ...)."""
    pytest.importorskip("absl")  # their transformations and inverse kinematics log with it
    root = tmp_path_factory.mktemp("reference")
    package = root / PACKAGE
    package.mkdir()
    (package / "__init__.py").write_text("")
    models = {}
    with zipfile.ZipFile(dm_control_wheel.wheel()) as archive:
        for name in ("rewards", "transformations", "inverse_kinematics"):
            source = archive.read(f"dm_control/utils/{name}.py").decode()
            for old, new in _IMPORTS:
                source = source.replace(old, new)
            (package / f"{name}.py").write_text(source)
        for name in ("arm.xml", "model_with_ball_joints.xml"):
            models[name] = archive.read(_ASSETS + name).decode()
    sys.path.insert(0, str(root))
    try:
        modules = {
            name: importlib.import_module(f"{PACKAGE}.{name}")
            for name in ("rewards", "transformations", "inverse_kinematics")
        }
        yield type("Reference", (), {**modules, "models": models})
    finally:
        sys.path.remove(str(root))
        for name in [n for n in sys.modules if n.startswith(PACKAGE)]:
            del sys.modules[name]


@pytest.fixture(autouse=True)
def _quiet():
    """Both sides log pole and convergence warnings, and numpy warns of the infinities
    and NaN given on purpose: the values are what is compared."""
    logging.disable(logging.WARNING)
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        yield
    logging.disable(logging.NOTSET)


def same(ours, reference) -> bool:
    """Equal to the last bit: type, dtype, shape, values, signs of zeros, NaN where NaN."""
    if type(ours) is not type(reference):
        return False
    a, b = np.asarray(ours), np.asarray(reference)
    return (
        a.dtype == b.dtype
        and a.shape == b.shape
        and np.array_equal(a, b, equal_nan=a.dtype.kind in "fc")
        and np.array_equal(np.signbit(a), np.signbit(b))
    )


# -- rewards ---------------------------------------------------------------------------------

SPECIAL = [0.0, -0.0, 5e-324, -5e-324, 1e-300, 1.0, -1.0, 2.0, 1e300, -1e300, np.inf, -np.inf,
           np.nan]  # fmt: skip
BOUNDS = [(0, 0), (0.0, 0.0), (-0.5, 0.2), (2, 2), (1.0, np.inf), (-np.inf, 0.3),
          (-np.inf, np.inf)]  # fmt: skip
MARGINS = [0.0, 0.7, 1.0, 1e-12, 1e12, np.inf]
VALUES_AT_MARGIN = [0.1, 0.5, 0.0, 1e-300, 1 - 1e-16, 1.0]


def _inputs(seed: int) -> list:
    rng = np.random.default_rng(seed)
    values = np.concatenate([rng.normal(0.0, 2.0, 43), SPECIAL])  # 56 values
    return [
        values,  # float64: Tolerance's fast path
        values.reshape(4, -1)[:, ::2],  # two dimensions, not contiguous
        values.astype(np.float32),  # dm_control keeps float32 in places
        np.array(0.25),  # 0-d: an array back, computed as numbers are
        *[float(x) for x in values[::6]],
        np.float64(-1.5),
        np.float32(1.5),
        3,
    ]


@pytest.mark.parametrize("sigmoid", rewards.SIGMOIDS)
def test_tolerance_equals_dm_controls_to_the_last_bit(theirs, sigmoid):
    compared = 0
    for bounds, margin, value in itertools.product(BOUNDS, MARGINS, VALUES_AT_MARGIN):
        try:
            theirs.rewards.tolerance(0.0, bounds, margin, sigmoid, value)
        except ValueError as expected:
            with pytest.raises(rewards.RewardError) as raised:
                rewards.tolerance(0.0, bounds, margin, sigmoid, value)
            assert str(raised.value) == str(expected)
            continue
        term = rewards.Tolerance(bounds, margin, sigmoid, value)
        for x in _inputs(len(str((bounds, margin, value)))):
            reference = theirs.rewards.tolerance(x, bounds, margin, sigmoid, value)
            assert same(term(x), reference), (x, bounds, margin, value)
            assert same(rewards.tolerance(x, bounds, margin, sigmoid, value), reference)
            compared += 1
    assert compared > 500


def test_tolerance_reused_across_calls_keeps_each_parameters_types(theirs):
    # `tolerance` reuses the Tolerance of equal parameters: equal values of other types
    # (a numpy scalar computes in its own dtype) must still give dm_control's bits.
    x = np.linspace(-2.0, 3.0, 11).astype(np.float32)
    for lower, upper, margin in [
        (0.5, 1.0, 0.7), (np.float64(0.5), np.float64(1.0), 0.7),
        (np.float32(0.5), 1.0, np.float32(0.7)), (0.5, 1.0, 0.7), (0, 1, 1), (0.0, 1.0, 1.0),
    ]:  # fmt: skip
        for value in (x, x.astype(np.float64), 1.25, np.float32(-0.5)):
            for _ in range(2):
                ours = rewards.tolerance(value, (lower, upper), margin, "long_tail", 0.25)
                reference = theirs.rewards.tolerance(
                    value, (lower, upper), margin, "long_tail", 0.25
                )
                assert same(ours, reference), (value, lower, upper, margin)


def test_tolerance_errors_are_dm_controls(theirs):
    cases = [
        ((1.0, 0.0), 0.1, "gaussian", 0.1),  # bounds out of order
        ((0.0, 1.0), -0.1, "gaussian", 0.1),  # negative margin
        ((0.0, 1.0), 1.0, "cubic", 0.1),  # unknown sigmoid
        ((0.0, 1.0), 1.0, "cubic", 0.0),  # value_at_margin is checked first
        ((0.0, 1.0), 1.0, "hyperbolic", 1.0),
        ((0.0, 1.0), 1.0, "cosine", -0.1),
    ]
    for bounds, margin, sigmoid, value in cases:
        with pytest.raises(ValueError) as expected:
            theirs.rewards.tolerance(0.5, bounds, margin, sigmoid, value)
        with pytest.raises(rewards.RewardError) as raised:
            rewards.Tolerance(bounds, margin, sigmoid, value)
        assert str(raised.value) == str(expected.value)


# -- transformations -------------------------------------------------------------------------


def _unit_quaternions(rng: np.random.Generator, n: int) -> np.ndarray:
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def _compare(theirs_function, ours_function, *args, **kwargs) -> None:
    reference = theirs_function(*args, **kwargs)
    assert same(ours_function(*args, **kwargs), reference), (ours_function.__name__, args)


@pytest.mark.parametrize("n", [1, 3, 40])
def test_batched_quaternion_functions_equal_dm_controls(theirs, n):
    t, rng = theirs.transformations, np.random.default_rng(n)
    q1, q2 = _unit_quaternions(rng, n), _unit_quaternions(rng, n)
    for name in ("quat_mul", "quat_diff", "quat_dist"):
        _compare(getattr(t, name), getattr(transformations, name), q1, q2)
        _compare(getattr(t, name), getattr(transformations, name), q1[0], q2[0])
    _compare(t.quat_mul, transformations.quat_mul, q1, q2[0])  # broadcast
    _compare(t.quat_mul, transformations.quat_mul, q1.astype(np.float32), q2)
    for name in ("quat_conj", "quat_inv", "quat_log"):
        _compare(getattr(t, name), getattr(transformations, name), q1)
        _compare(getattr(t, name), getattr(transformations, name), q1[0])
    _compare(t.quat_inv, transformations.quat_inv, 3.0 * q1)
    _compare(t.quat_conj, transformations.quat_conj, np.array([1, 2, 3, 4]))  # ints: float64
    axis_angles = rng.normal(size=(n, 3))
    axis_angles[0] = 0.0
    _compare(t.axisangle_to_quat, transformations.axisangle_to_quat, axis_angles)
    _compare(t.axisangle_to_quat, transformations.axisangle_to_quat, axis_angles, tol=0.5)
    _compare(t.axisangle_to_quat, transformations.axisangle_to_quat, axis_angles[-1])
    angles = rng.uniform(-np.pi, np.pi, size=(n, 3))
    for ordering, full in itertools.product(["XYZ", "ZXZ", "YYX", "ZYX"], [False, True]):
        _compare(t.euler_to_rmat, transformations.euler_to_rmat, angles, ordering, full)
    for name, full in itertools.product(("x", "y", "z"), [False, True]):
        function = f"rotation_{name}_axis"
        ours_function, their_function = getattr(transformations, function), getattr(t, function)
        _compare(their_function, ours_function, angles[:, 0], full)
        _compare(their_function, ours_function, float(angles[0, 0]), full)
    _compare(t.rotation_matrix_2d, transformations.rotation_matrix_2d, angles[:, 0])
    _compare(t.rotation_matrix_2d, transformations.rotation_matrix_2d, angles[0, 0])


def test_single_rotation_conversions_equal_dm_controls(theirs):
    t, rng = theirs.transformations, np.random.default_rng(7)
    orderings = list(t._eulermap)
    assert orderings == list(transformations._eulermap)
    for i, quat in enumerate(_unit_quaternions(rng, 400)):
        if i % 5 == 0:  # on axes and at poles
            quat = np.round(quat, 1) / np.linalg.norm(np.round(quat, 1))
        vector = rng.normal(size=3)
        _compare(t.quat_rotate, transformations.quat_rotate, quat, vector)
        _compare(t.quat_to_mat, transformations.quat_to_mat, quat)
        _compare(t.quat_to_mat, transformations.quat_to_mat, 7.0 * quat)
        _compare(t.quat_to_axisangle, transformations.quat_to_axisangle, quat)
        matrix = t.quat_to_mat(quat)
        _compare(t.mat_to_quat, transformations.mat_to_quat, matrix)
        _compare(t.mat_to_quat, transformations.mat_to_quat, matrix[:3, :3])
        ordering = orderings[i % len(orderings)]
        _compare(t.quat_to_euler, transformations.quat_to_euler, quat, ordering)
        angles = rng.uniform(-np.pi, np.pi, 3)
        if i % 3 == 0:  # the poles of every ordering, and multiples of pi / 2
            angles = np.round(angles * 2 / np.pi) * np.pi / 2
        _compare(t.euler_to_quat, transformations.euler_to_quat, angles, ordering)
        _compare(
            t.rmat_to_euler,
            transformations.rmat_to_euler,
            t.euler_to_rmat(angles, ordering),
            ordering,
        )
    _compare(t.quat_to_mat, transformations.quat_to_mat, np.zeros(4))  # the identity
    identity = np.array([1.0, 0.0, 0.0, 0.0])
    _compare(t.quat_to_axisangle, transformations.quat_to_axisangle, identity)  # zeros


def test_unknown_orderings_and_non_unit_quaternions_raise_what_dm_controls_raise(theirs):
    t = theirs.transformations
    with pytest.raises(KeyError):
        t.rmat_to_euler(np.eye(3))  # the default ordering, 'ZXZ', is not invertible there
    with pytest.raises(KeyError):
        transformations.rmat_to_euler(np.eye(3))
    with pytest.raises(ValueError):
        t.quat_to_axisangle(np.array([1.5, 0.0, 0.0, 0.0]))
    with pytest.raises(ValueError):
        transformations.quat_to_axisangle(np.array([1.5, 0.0, 0.0, 0.0]))


# -- inverse kinematics ----------------------------------------------------------------------

_ARM_JOINTS = ["joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"]


def _same_result(ours, reference) -> bool:
    return (
        ours.qpos.tobytes() == reference.qpos.tobytes()
        and same(ours.err_norm, reference.err_norm)
        and ours.steps == reference.steps
        and ours.success == reference.success
    )


def test_qpos_from_site_pose_equals_dm_controls_on_our_physics(theirs):
    """dm_control's own function runs on mjcf.Physics (it needs only what dm_control's
    Physics has: named views, copy, name2id): from the same random starts, targets and
    options, the same steps to the last bit."""
    rng = np.random.default_rng(3)
    successes = 0
    for trial in range(24):
        physics = mjcf.Physics.from_xml_string(theirs.models["arm.xml"])
        physics.data.qpos[:] = rng.uniform(-2.0, 2.0, physics.model.nq)
        options = {
            "site_name": "gripsite",
            "target_pos": None if trial % 3 == 2 else rng.uniform(-0.5, 0.5, 3),
            "target_quat": None if trial % 3 == 0 else rng.normal(size=4),
            "joint_names": [None, _ARM_JOINTS, tuple(_ARM_JOINTS[:4]), np.array(_ARM_JOINTS)][
                trial % 4
            ],
            "max_steps": [100, 5, 30][trial % 3],
            "rot_weight": [1.0, 0.5][trial % 2],
        }
        before = physics.data.qpos.copy()
        reference = theirs.inverse_kinematics.qpos_from_site_pose(physics, **options)
        result = inverse_kinematics.qpos_from_site_pose(physics, **options)
        assert _same_result(result, reference), trial
        np.testing.assert_array_equal(physics.data.qpos, before)  # not inplace: untouched
        successes += result.success
    assert 6 <= successes < 24  # both outcomes compared


def test_qpos_from_site_pose_inplace_with_ball_joints_equals_dm_controls(theirs):
    rng = np.random.default_rng(4)
    for _ in range(6):
        physics = mjcf.Physics.from_xml_string(theirs.models["model_with_ball_joints.xml"])
        copy = physics.copy()
        options = {
            "site_name": "gripsite",
            "target_pos": rng.uniform(-0.1, 0.1, 3),
            "joint_names": ["joint_1", "joint_2"],
            "inplace": True,
        }
        reference = theirs.inverse_kinematics.qpos_from_site_pose(physics, **options)
        result = inverse_kinematics.qpos_from_site_pose(copy, **options)
        assert _same_result(result, reference)
        assert result.qpos.base is not None  # a view of the physics' qpos, as dm_control's
        assert copy.data.qpos.tobytes() == physics.data.qpos.tobytes()


def test_nullspace_method_equals_dm_controls(theirs):
    rng = np.random.default_rng(5)
    for rows, columns, strength in itertools.product([3, 6], [2, 7], [0.0, 0.03]):
        jacobian, delta = rng.normal(size=(rows, columns)), rng.normal(size=rows)
        reference = theirs.inverse_kinematics.nullspace_method(jacobian, delta, strength)
        assert same(inverse_kinematics.nullspace_method(jacobian, delta, strength), reference)
