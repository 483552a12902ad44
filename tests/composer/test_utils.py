"""composer.utils on its own (no dm_control needed): the values a user relies on, checked
against MuJoCo's own functions and real robots, the errors, and the import rules.
(tests/composer/test_utils_reference.py compares the values with dm_control's modules.)"""

from __future__ import annotations

import itertools
import logging
import pickle
import subprocess
import sys
import warnings

import mujoco
import numpy as np
import pytest

import composer
import mjcf
import tasks.rewards
from composer.utils import inverse_kinematics, rewards, transformations
from entities import robots
from tests.conftest import REPO

# -- rewards ---------------------------------------------------------------------------------


@pytest.mark.parametrize("sigmoid", rewards.SIGMOIDS)
def test_tolerance_is_one_inside_and_value_at_margin_one_margin_out(sigmoid):
    term = rewards.Tolerance(bounds=(-1.0, 2.0), margin=0.5, sigmoid=sigmoid, value_at_margin=0.3)
    inside = np.array([-1.0, 0.0, 2.0])
    np.testing.assert_array_equal(term(inside), 1.0)
    assert term(2.5) == pytest.approx(0.3, abs=1e-12)
    assert term(-1.5) == pytest.approx(0.3, abs=1e-12)
    outside = term(np.array([2.1, 2.4, 2.5, 2.6]))
    assert np.all(np.diff(outside) < 0) and np.all(outside < 1.0)
    if sigmoid in ("cosine", "linear", "quadratic"):  # these reach 0 at a finite distance
        ends = rewards.tolerance(np.array([1.0, 3.0]), margin=1.0, sigmoid=sigmoid,
                                 value_at_margin=0.0)  # fmt: skip
        np.testing.assert_array_equal(ends, [0.0, 0.0])


def test_tolerance_without_margin_is_an_indicator_and_checks_no_sigmoid():
    assert rewards.tolerance(1.0, bounds=(0.0, 1.0)) == 1.0
    assert rewards.tolerance(1.0 + 1e-15, bounds=(0.0, 1.0)) == 0.0
    assert rewards.tolerance(5.0, bounds=(0.0, np.inf)) == 1.0
    # dm_control ignores the sigmoid and value_at_margin when margin is 0.
    assert rewards.tolerance(0.0, sigmoid="cubic", value_at_margin=7) == 1.0


def test_tolerance_returns_dm_controls_types():
    assert type(rewards.tolerance(0.3, margin=1.0)) is float
    assert type(rewards.tolerance(np.float64(0.3), margin=1.0)) is float
    assert type(rewards.tolerance(3, margin=1.0)) is float
    zero_d = rewards.tolerance(np.array(0.3), margin=1.0)
    assert type(zero_d) is np.ndarray and zero_d.shape == ()
    assert rewards.tolerance(np.zeros((2, 3)), margin=1.0).shape == (2, 3)
    float32 = np.array([0.5, 2.0], dtype=np.float32)
    assert rewards.tolerance(float32, margin=1.0, sigmoid="linear").dtype == np.float32
    assert rewards.tolerance(float32, margin=1.0).dtype == np.float64  # its scale is float64


def test_tolerance_errors_are_value_errors_with_dm_controls_messages():
    cases = {
        "Lower bound must be <= upper bound.": {"bounds": (1.0, 0.0)},
        "`margin` must be non-negative.": {"margin": -1.0},
        "`value_at_1` must be strictly between 0 and 1, got 0.": {
            "margin": 1.0, "value_at_margin": 0,
        },
        "`value_at_1` must be nonnegative and smaller than 1, got 1.": {
            "margin": 1.0, "sigmoid": "linear", "value_at_margin": 1,
        },
        "Unknown sigmoid type 'cubic'.": {"margin": 1.0, "sigmoid": "cubic"},
    }  # fmt: skip
    for message, options in cases.items():
        with pytest.raises(rewards.RewardError) as raised:
            rewards.Tolerance(**options)  # checked when built, not at the first call
        assert str(raised.value) == message
        assert isinstance(raised.value, ValueError | composer.TaskError)


SPECIAL = np.array([0.0, -0.0, 5e-324, 1e-300, -1.0, 1.0, 2.0, 1e300, -1e300, np.inf, -np.inf,
                    np.nan])  # fmt: skip


@pytest.mark.parametrize("sigmoid", rewards.SIGMOIDS)
def test_tolerance_of_a_float64_array_is_the_general_formula_to_the_last_bit(sigmoid):
    """Tolerance takes a shortcut for float64 arrays; a big-endian copy of the same values
    goes the general way (dm_control's formula as written), to the same bits."""
    random = np.random.default_rng(0).normal(0.0, 2.0, 100)
    xs = np.concatenate([random, SPECIAL])
    for bounds, margin, value in itertools.product(
        [(0.0, 0.0), (-0.5, 0.2), (1.0, np.inf)], [0.0, 0.7, 1.0, np.inf], [0.0, 0.3, 1e-300]
    ):
        if value == 0.0 and sigmoid not in ("cosine", "linear", "quadratic"):
            continue
        with np.errstate(all="ignore"):  # infinities, on purpose (a scale too: tanh_squared's)
            term = rewards.Tolerance(bounds, margin, sigmoid, value)
            fast, general = term(xs), term(xs.astype(">f8"))
        assert fast.dtype == general.dtype == np.float64
        assert np.array_equal(fast, general, equal_nan=True)
        assert np.array_equal(np.signbit(fast), np.signbit(general))


@pytest.mark.parametrize("sigmoid", rewards.SIGMOIDS)
def test_column_tolerance_is_each_columns_tolerance_to_the_last_bit(sigmoid):
    """Terms of one sigmoid and kind of bounds, with their own bounds, margins (1 among
    them: not divided by) and values at the margin, computed together."""
    families = [
        [((0.0, 0.0), 2.0, 0.1), ((0.0, 0.0), 1.0, 0.3), ((0.0, 0.0), 5.0, 0.1)],
        [((1.2, np.inf), 0.6, 0.1), ((10.0, np.inf), 1.0, 0.5), ((0.9, np.inf), 1.9, 0.2)],
        [((-np.inf, 0.3), 0.7, 0.4), ((-np.inf, -2.0), 1.0, 0.1)],
        [((-0.5, 0.2), 0.7, 0.3), ((0.0, 1.0), 1e-12, 0.1), ((2.0, 2.0), np.inf, 0.1)],
    ]
    random = np.random.default_rng(3).normal(0.0, 3.0, (40, 1))
    for family in families:
        terms = [rewards.Tolerance(b, m, sigmoid, v) for b, m, v in family]
        if sigmoid in ("cosine", "linear", "quadratic"):  # a value of 0 (scale 1) too
            terms.append(rewards.Tolerance(family[0][0], family[0][1], sigmoid, 0.0))
        xs = np.concatenate([random, SPECIAL[:, None]]) + np.zeros(len(terms))
        xs[:, 1:] = np.roll(xs[:, 1:], 3, axis=0)  # other values in other columns
        with np.errstate(all="ignore"):
            together = rewards.ColumnTolerance(terms)(xs)
            apart = np.stack([term(xs[:, k]) for k, term in enumerate(terms)], axis=1)
        assert together.dtype == np.float64 and together.shape == xs.shape
        assert together.tobytes() == apart.tobytes(), (sigmoid, family)
        again = pickle.loads(pickle.dumps(rewards.ColumnTolerance(terms)))
        with np.errstate(all="ignore"):  # one row, one vector, and the rows again
            for rows in (slice(0, 1), 5, slice(None)):
                assert again(xs[rows]).tobytes() == together[rows].tobytes()


def test_column_tolerance_of_margin_zero_terms_is_theirs_and_refuses_mixed_terms():
    terms = [rewards.Tolerance((-0.25, 0.25)), rewards.Tolerance((0.995, 1.0))]
    xs = np.array([[0.0, 1.0], [-0.25, 0.995], [0.3, 0.9], [np.nan, np.inf], [-np.inf, 1.0]])
    together = rewards.ColumnTolerance(terms)(xs)
    assert together.tobytes() == np.stack([terms[0](xs[:, 0]), terms[1](xs[:, 1])], 1).tobytes()
    assert together.tolist() == [[1, 1], [1, 1], [0, 0], [0, 0], [0, 1]]
    mixed = [
        [rewards.Tolerance(margin=1.0), rewards.Tolerance(margin=1.0, sigmoid="linear")],
        [rewards.Tolerance(margin=1.0), rewards.Tolerance((1.0, np.inf), margin=1.0)],
        [rewards.Tolerance(margin=1.0), rewards.Tolerance((0.0, 1.0))],
        [rewards.Tolerance((-np.inf, np.inf), margin=1.0)],  # no finite bound
        [],
    ]
    for terms in mixed:
        with pytest.raises(rewards.RewardError):
            rewards.ColumnTolerance(terms)
    columns = rewards.ColumnTolerance([rewards.Tolerance(margin=2.0)] * 2)
    for wrong in (np.zeros((3, 3)), np.zeros(2, dtype=np.float32), [0.0, 1.0]):
        with pytest.raises(rewards.RewardError, match=r"float64 array of shape \(\.\.\., 2\)"):
            columns(wrong)


def test_tolerance_called_again_computes_as_its_parameters_types_say():
    """`tolerance` reuses what it built for the same parameters; a numpy float64 margin
    is not the Python float of the same value (it makes a float32 input's result float64)."""
    float32 = np.array([0.5, 2.0], dtype=np.float32)
    for _ in range(2):
        assert rewards.tolerance(float32, margin=1.0, sigmoid="linear").dtype == np.float32
        assert rewards.tolerance(float32, margin=np.float64(1.0), sigmoid="linear").dtype == (
            np.float64
        )
        assert rewards.tolerance(float32, margin=1, sigmoid="linear").dtype == np.float32
    with pytest.raises(rewards.RewardError):  # a bad set is refused every call, never kept
        rewards.tolerance(0.5, bounds=(1.0, 0.0))
    with pytest.raises(rewards.RewardError):
        rewards.tolerance(0.5, bounds=(1.0, 0.0))


def test_row_means_and_norms_are_numpys_to_the_last_bit():
    rows = np.random.default_rng(1).normal(0.0, 3.0, (50, 7))
    assert tasks.rewards.row_means(rows).tobytes() == rows.mean(axis=1).tobytes()
    assert tasks.rewards.row_norms(rows).tobytes() == np.linalg.norm(rows, axis=1).tobytes()


def test_tasks_rewards_is_composer_utils_rewards():
    assert tasks.rewards.tolerance is rewards.tolerance
    assert tasks.rewards.Tolerance is rewards.Tolerance


# -- transformations -------------------------------------------------------------------------


def _unit_quaternions(n: int, seed: int = 0) -> np.ndarray:
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def test_quaternion_functions_agree_with_mujocos():
    quats, others = _unit_quaternions(50), _unit_quaternions(50, seed=1)
    products = transformations.quat_mul(quats, others)
    vector = np.array([0.3, -1.0, 2.0])
    for quat, other, product in zip(quats, others, products, strict=True):
        expected = np.empty(4)
        mujoco.mju_mulQuat(expected, quat, other)
        np.testing.assert_allclose(product, expected, atol=1e-15)
        matrix = np.empty(9)
        mujoco.mju_quat2Mat(matrix, quat)
        np.testing.assert_allclose(transformations.quat_to_mat(quat)[:3, :3].ravel(), matrix,
                                   atol=1e-15)  # fmt: skip
        back = transformations.mat_to_quat(matrix.reshape(3, 3))
        np.testing.assert_allclose(back * np.sign(back[0] * quat[0]), quat, atol=1e-15)
        rotated = np.empty(3)
        mujoco.mju_rotVecQuat(rotated, vector, quat)
        np.testing.assert_allclose(transformations.quat_rotate(quat, vector), rotated, atol=1e-14)
        axis_angle = transformations.quat_to_axisangle(quat)
        angle = np.linalg.norm(axis_angle)
        from_mujoco = np.empty(4)
        mujoco.mju_axisAngle2Quat(from_mujoco, axis_angle / angle, angle)
        np.testing.assert_allclose(transformations.axisangle_to_quat(axis_angle), from_mujoco,
                                   atol=1e-15)  # fmt: skip
        np.testing.assert_allclose(from_mujoco * np.sign(from_mujoco[0] * quat[0]), quat,
                                   atol=1e-14)  # fmt: skip
    identity = transformations.quat_mul(quats, transformations.quat_inv(quats))
    np.testing.assert_allclose(identity, np.tile([1.0, 0, 0, 0], (50, 1)), atol=1e-15)
    np.testing.assert_allclose(transformations.quat_dist(quats, quats), 0.0, atol=1e-9)
    assert transformations.quat_dist(quats, others).shape == (50, 1)


@pytest.mark.parametrize("ordering", ["XYZ", "ZYX", "XZY", "YZX", "ZXY", "YXZ"])
def test_euler_angles_are_mujocos_intrinsic_sequences_and_invert(ordering):
    angles = np.random.default_rng(2).uniform(-1.5, 1.5, size=(20, 3))
    for euler in angles:
        expected = np.empty(4)
        mujoco.mju_euler2Quat(expected, euler, ordering.lower())  # lowercase: intrinsic
        quat = transformations.euler_to_quat(euler, ordering)
        np.testing.assert_allclose(quat * np.sign(quat[0] * expected[0]), expected, atol=1e-15)
        matrix = transformations.euler_to_rmat(euler, ordering)
        np.testing.assert_allclose(transformations.rmat_to_euler(matrix, ordering), euler,
                                   atol=1e-12)  # fmt: skip
    batched = transformations.euler_to_rmat(angles, ordering, full=True)
    assert batched.shape == (20, 4, 4)
    np.testing.assert_array_equal(batched[:, 3], np.tile([0.0, 0, 0, 1], (20, 1)))


def test_a_pole_gives_angles_of_the_same_rotation_and_warns_once(caplog):
    matrix = transformations.euler_to_rmat([0.3, np.pi / 2, 0.2], "XYZ")
    with caplog.at_level(logging.WARNING, logger="composer.utils.transformations"):
        angles = [transformations.rmat_to_euler(matrix, "XYZ") for _ in range(3)]
    assert angles[0][0] == 0.0 and angles[0][1] == np.pi / 2
    np.testing.assert_allclose(transformations.euler_to_rmat(angles[0], "XYZ"), matrix,
                               atol=1e-12)  # fmt: skip
    assert [record.getMessage() for record in caplog.records].count("Angle at North Pole") <= 1


def test_transformation_errors():
    for call in (
        lambda: transformations.rmat_to_euler(np.eye(3)),  # dm_control's default, 'ZXZ'
        lambda: transformations.euler_to_rmat([0.1, 0.2, 0.3], "XQZ"),
    ):
        with pytest.raises(transformations.EulerOrderingError, match="ordering") as raised:
            call()
        assert isinstance(raised.value, KeyError | composer.Error)
    with pytest.raises(transformations.TransformationError, match="unit quaternion"):
        transformations.quat_to_axisangle(np.array([1.5, 0.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match="quat_log"):
        transformations.quat_log(np.array([2.0, 0.0, 0.0, 0.0]))


def test_inputs_dm_control_refuses_are_taken_and_zero_rotations_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(transformations.axisangle_to_quat(np.zeros(3)),
                                      [1.0, 0.0, 0.0, 0.0])  # fmt: skip
        np.testing.assert_array_equal(transformations.quat_to_axisangle([1.0, 0, 0, 0]), 0.0)
    assert transformations.rotation_x_axis(np.array(0.3)).shape == (3, 3)
    assert transformations.quat_mul([1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]).tolist() == [
        0.0, 1.0, 0.0, 0.0
    ]  # fmt: skip


# -- inverse kinematics ----------------------------------------------------------------------


@pytest.fixture(scope="module")
def ur5e():
    """The shipped UR5e with its 2F-85 gripper, compiled; the arm's six joints."""
    robot = robots.ur5e_with_2f85()
    joints = robot.arm.mjcf_model.find_all("joint", exclude_attachments=True)
    return robot, mjcf.Physics.from_mjcf_model(robot.mjcf_model), joints


def _pose_at(physics: mjcf.Physics, site: mjcf.Element) -> tuple[np.ndarray, np.ndarray]:
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, physics.bind(site).xmat)
    return physics.bind(site).xpos.copy(), quat


def test_qpos_from_site_pose_puts_a_real_grippers_tool_point_at_a_pose(ur5e):
    robot, physics, joints = ur5e
    names = [joint.full_identifier for joint in joints]
    physics.reset()
    physics.bind(joints).qpos = [0.4, -1.2, 1.5, -1.0, -1.3, 0.6]
    target_pos, target_quat = _pose_at(physics, robot.tcp)
    physics.reset()
    start = physics.data.qpos.copy()

    result = inverse_kinematics.qpos_from_site_pose(
        physics, robot.tcp.full_identifier, target_pos, target_quat, names
    )
    assert result.success and result.err_norm < 1e-14 and result.steps < 100
    np.testing.assert_array_equal(physics.data.qpos, start)  # a copy was worked on
    gripper = [i for i in range(physics.model.nq) if i >= len(joints)]
    np.testing.assert_array_equal(result.qpos[gripper], start[gripper])  # not named: still

    inverse_kinematics.qpos_from_site_pose(
        physics, robot.tcp.full_identifier, target_pos, target_quat, names, inplace=True
    )
    np.testing.assert_array_equal(physics.data.qpos, result.qpos)
    position, quat = _pose_at(physics, robot.tcp)  # bindings see the new positions
    np.testing.assert_allclose(position, target_pos, atol=1e-12)
    np.testing.assert_allclose(quat * np.sign(quat[0] * target_quat[0]), target_quat, atol=1e-12)


def test_qpos_from_site_pose_that_cannot_converge_says_so(ur5e, caplog):
    robot, physics, _ = ur5e
    physics.reset()
    with caplog.at_level(logging.WARNING, logger="composer.utils.inverse_kinematics"):
        result = inverse_kinematics.qpos_from_site_pose(
            physics, robot.tcp.full_identifier, target_pos=[5.0, 0.0, 0.0], max_steps=3
        )  # out of reach
    assert not result.success and result.steps == 2 and result.err_norm > 1.0
    assert "Failed to converge after 2 steps" in caplog.text


def test_qpos_from_site_pose_errors(ur5e):
    robot, physics, _ = ur5e
    site = robot.tcp.full_identifier
    with pytest.raises(inverse_kinematics.InverseKinematicsError, match="target"):
        inverse_kinematics.qpos_from_site_pose(physics, site)
    with pytest.raises(ValueError, match="joint_names"):
        inverse_kinematics.qpos_from_site_pose(physics, site, [0, 0, 1], joint_names="ur5e/elbow")
    with pytest.raises(ValueError, match="max_steps"):
        inverse_kinematics.qpos_from_site_pose(physics, site, [0, 0, 1], max_steps=0)
    with pytest.raises(mjcf.NotFoundError, match="site named 'pinch'"):
        inverse_kinematics.qpos_from_site_pose(physics, "pinch", [0, 0, 1])
    with pytest.raises(KeyError, match="joint named 'elbow'"):
        inverse_kinematics.qpos_from_site_pose(physics, site, [0, 0, 1], joint_names=["elbow"])


# -- imports ---------------------------------------------------------------------------------


def test_import_composer_leaves_rewards_and_inverse_kinematics_unloaded():
    """`import composer` loads none of composer.utils (composer.variation's rotations, which
    use transformations as dm_control's do, load with composer.variation); each module
    loads when asked for, `composer.utils.rewards` included."""
    script = (
        "import sys, composer, composer.utils\n"
        "print(sorted(m for m in sys.modules if m.startswith('composer.utils.')))\n"
        "composer.utils.rewards.tolerance(0.0)\n"
        "print('composer.utils.rewards' in sys.modules)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=True
    ).stdout.split("\n")
    assert out[:2] == ["[]", "True"]
