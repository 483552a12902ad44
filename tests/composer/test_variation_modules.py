"""composer.variation's modules as dm_control code uses them: draws equal to numpy's own for
the same random state, nested evaluation, noises, rotations (against MuJoCo's quaternion
functions), colors, math, sequences, broadcasting, and the variators' bookkeeping."""

from __future__ import annotations

import collections
import copy
import operator
import pickle

import mujoco
import numpy as np
import pytest

import composer
import mjcf
from composer import variation
from composer.variation import (
    colors,
    deterministic,
    distributions,
    noises,
    rotations,
    variation_broadcaster,
)
from composer.variation import math as vmath
from tests.composer.scenes import Block


def rs(seed: int = 0) -> np.random.RandomState:
    return np.random.RandomState(seed)


class Recorder(variation.Variation):
    """Records the arguments it is called with and returns a label."""

    def __init__(self, label: str, calls: list) -> None:
        self.label, self.calls = label, calls

    def __call__(self, initial_value=None, current_value=None, random_state=None):
        self.calls.append((self.label, initial_value, current_value, random_state))
        return self.label


# -- distributions: one call of numpy's method of the same name ---------------------------


@pytest.mark.parametrize(
    ("distribution", "draw"),
    [
        (distributions.UniformInteger(2, 9), lambda r, size: r.randint(2, 9, size=size)),
        (distributions.UniformInteger(5), lambda r, size: r.randint(5, size=size)),
        (distributions.UniformChoice(["a", "b"]), lambda r, size: r.choice(["a", "b"], size)),
        (distributions.Exponential(3), lambda r, size: r.exponential(3, size)),
        (distributions.Poisson(4), lambda r, size: r.poisson(4, size)),
        (distributions.Bernoulli(0.3), lambda r, size: r.binomial(1, 0.3, size)),
        (distributions.LogNormal(1, 0.5), lambda r, size: r.lognormal(1, 0.5, size)),
    ],
)
def test_distributions_draw_what_numpy_draws(distribution, draw):
    assert np.array_equal(distribution(random_state=rs(3)), draw(rs(3), None))
    shaped = distribution(initial_value=np.zeros((2, 3)), random_state=rs(4))
    assert np.array_equal(shaped, draw(rs(4), (2, 3)))
    one = type(distribution)(*distribution._args, **distribution._kwargs, single_sample=True)
    assert np.shape(one(initial_value=np.zeros(3), random_state=rs())) == ()


def test_parameters_that_vary_are_drawn_first_by_sorted_keyword():
    # dm_control evaluates keyword parameters as dm-tree does: sorted by name, so 'high'
    # before 'low', then draws with the values.
    uniform = distributions.Uniform(low=distributions.Uniform(0, 1), high=distributions.Normal())
    r = rs(7)
    high, low = r.normal(0.0, 1.0), r.uniform(0, 1)
    assert uniform(random_state=rs(7)) == r.uniform(low, high)


def test_a_distribution_without_random_state_draws_from_numpy_global_state():
    np.random.seed(12)
    expected = np.random.RandomState(12).normal(2.0, 0.5, size=3)
    np.testing.assert_array_equal(distributions.Normal(2.0, 0.5)(np.zeros(3)), expected)


def test_a_generator_works_as_random_state():
    generator = np.random.default_rng(5)
    assert distributions.UniformInteger(3, 6)(random_state=generator) in (3, 4, 5)
    draws = distributions.Normal()(initial_value=np.zeros(4), random_state=np.random.default_rng(2))
    np.testing.assert_array_equal(draws, np.random.default_rng(2).normal(0, 1, size=(4,)))


def test_uniform_point_on_sphere_is_unit_and_shaped_per_element():
    points = distributions.UniformPointOnSphere()(initial_value=np.zeros(5), random_state=rs())
    assert points.shape == (5, 3)
    np.testing.assert_allclose(np.linalg.norm(points, axis=-1), 1.0)
    raw = rs().normal(size=(5, 3))
    np.testing.assert_allclose(points, raw / np.linalg.norm(raw, axis=-1, keepdims=True))


def test_biased_random_walk_follows_its_recursion_and_refuses_negative_parameters():
    walk = distributions.BiasedRandomWalk(stdev=2.0, timescale=4.0)
    r = rs(9)
    retain = np.exp(-1 / 4.0)
    scale = 2.0 * np.sqrt(1 - retain**2)
    expected, value = [], 0.0
    for _ in range(5):
        value = retain * value + r.normal(0.0, scale)
        expected.append(value)
    state = rs(9)
    np.testing.assert_allclose([walk(random_state=state) for _ in range(5)], expected)
    with pytest.raises(composer.VariationError, match="`stdev` must be >= 0, got -1"):
        distributions.BiasedRandomWalk(stdev=-1)
    with pytest.raises(ValueError, match="`timescale` must be >= 0"):
        distributions.BiasedRandomWalk(timescale=-2)


def test_bad_parameters_raise_variation_error_a_value_error_naming_them():
    with pytest.raises(composer.VariationError, match=r"Uniform.*'low': \[0, 0\]"):
        distributions.Uniform([0, 0], [1, 1, 1])(random_state=rs())
    with pytest.raises(ValueError, match="Normal"):
        distributions.Normal(0, -1)(random_state=rs())


def test_distribution_subclasses_use_dm_controls_extension_point():
    class Cycle(distributions.Distribution):
        """Returns its choices in order (dm_control's tests write such helpers)."""

        def __init__(self, choices, single_sample=False):
            super().__init__(choices, single_sample=single_sample)
            self._idx = 0

        def _callable(self, random_state):
            def next_item(*args, **kwargs):
                item = self._args[0][self._idx]
                self._idx = (self._idx + 1) % len(self._args[0])
                return item

            return next_item

    cycle = Cycle([1, 2])
    assert [variation.evaluate(cycle, random_state=rs()) for _ in range(3)] == [1, 2, 1]


def test_distributions_compare_copy_and_pickle_by_parameters():
    uniform = distributions.Uniform(np.zeros(3), np.ones(3))
    assert uniform == distributions.Uniform(np.zeros(3), np.ones(3))
    assert uniform != distributions.Uniform(np.zeros(3), np.full(3, 2.0))
    assert uniform != distributions.Normal(np.zeros(3), np.ones(3))
    assert uniform.high[0] == 1.0  # keyword parameters read as attributes
    with pytest.raises(AttributeError, match="no attribute 'width'"):
        _ = uniform.width
    for clone in (copy.deepcopy(uniform), pickle.loads(pickle.dumps(uniform))):
        assert clone == uniform
        np.testing.assert_array_equal(clone(random_state=rs(1)), uniform(random_state=rs(1)))


def test_choice_keeps_the_choice_itself_and_draws_as_uniform_choice():
    options = [{"name": "a"}, {"name": "b"}, {"name": "c"}]
    picks = [distributions.Choice(options)(random_state=rs(s)) for s in range(10)]
    assert all(any(p is o for o in options) for p in picks)
    indices = [distributions.UniformChoice([0, 1, 2])(random_state=rs(s)) for s in range(10)]
    assert [options.index(p) for p in picks] == indices
    assert distributions.Choice([1, 2], p=[0, 1])(random_state=rs()) == 2
    with pytest.raises(composer.VariationError, match="at least one"):
        distributions.Choice([])


# -- evaluate and arithmetic --------------------------------------------------------------


def test_evaluate_replaces_callables_in_nested_structures_keeping_their_types():
    point = collections.namedtuple("Point", "x y")
    structure = (
        distributions.Uniform(0, 1),
        [2.0, deterministic.Constant("c")],
        {"b": deterministic.Constant(1), "a": (3, deterministic.Constant(4))},
        point(deterministic.Constant(5), 6),
        np.arange(2),
        "text",
    )
    value = variation.evaluate(structure, random_state=rs(2))
    assert value[0] == rs(2).uniform(0, 1)
    assert value[1] == [2.0, "c"]
    assert value[2] == {"b": 1, "a": (3, 4)} and list(value[2]) == ["b", "a"]
    assert value[3] == point(5, 6) and type(value[3]) is point
    assert value[4] is structure[4] and value[5] == "text"
    assert variation.evaluate(lambda random_state: random_state, random_state=7) == 7


def test_evaluate_draws_mapping_entries_by_sorted_key_depth_first():
    calls: list = []
    structure = [Recorder("x", calls), {"z": Recorder("z", calls), "a": Recorder("a", calls)}]
    variation.evaluate(structure, 1, 2, 3)
    assert [label for label, *_ in calls] == ["x", "a", "z"]
    assert {tuple(args) for _, *args in calls} == {(1, 2, 3)}


@pytest.mark.parametrize("name", ["add", "sub", "mul", "truediv", "floordiv", "pow"])
def test_binary_operators_apply_to_values_as_they_are(name):
    op = getattr(operator, name)
    seven, two = deterministic.Constant(7), deterministic.Constant(2)
    assert variation.evaluate(op(seven, 2)) == op(7, 2)
    assert variation.evaluate(op(7, two)) == op(7, 2)
    assert variation.evaluate(op(seven, two)) == op(7, 2)
    assert op(seven, two) == op(seven, two) and op(seven, two) != op(two, seven)


def test_unary_minus_and_indexing():
    vector = deterministic.Constant(np.array([4, 5, 6]))
    np.testing.assert_array_equal(variation.evaluate(-vector), [-4, -5, -6])
    np.testing.assert_array_equal(variation.evaluate(vector[[2, 0]]), [6, 4])
    assert str(vector[1]) == "[4 5 6][1]"
    # Lists are combined as Python combines them, as dm_control does.
    assert variation.evaluate(operator.add(deterministic.Constant([1]), [2])) == [1, 2]


# -- noises, deterministic, colors, math ---------------------------------------------------


def test_noises_add_to_or_multiply_the_initial_or_the_current_value():
    normal = distributions.Normal(0, 0.1)
    drawn = rs(1).normal(0, 0.1, size=3)
    start = np.array([1.0, 2.0, 3.0])
    added = noises.Additive(normal)(
        initial_value=start, current_value=start * 9, random_state=rs(1)
    )
    np.testing.assert_array_equal(added, start + drawn)
    walked = noises.Additive(normal, cumulative=True)(
        initial_value=start, current_value=start * 9, random_state=rs(1)
    )
    np.testing.assert_array_equal(walked, start * 9 + drawn)
    scaled = noises.Multiplicative(2.0, cumulative=True)(initial_value=1.0, current_value=3.0)
    assert scaled == 6.0
    assert noises.Additive(normal) == noises.Additive(distributions.Normal(0, 0.1))
    assert noises.Additive(normal) != noises.Additive(normal, cumulative=True)


def test_sequence_cycles_and_evaluates_its_items_and_identity_is_the_current_value():
    sequence = deterministic.Sequence([1, distributions.Uniform(5, 6), 3])
    values = [sequence(random_state=rs()) for _ in range(4)]
    assert values[0] == 1 and 5 <= values[1] < 6 and values[2:] == [3, 1]
    assert deterministic.Identity()(initial_value=1, current_value=2) == 2
    assert repr(deterministic.Constant(np.array([1]))) == "Constant(array([1]))"


def test_colors_are_rgba_arrays():
    np.testing.assert_array_equal(colors.RgbVariation(0.1, 0.2, 0.3)(), [0.1, 0.2, 0.3, 1.0])
    np.testing.assert_allclose(
        colors.HsvVariation(1 / 3, 1.0, 0.5, alpha=0.25)(), [0.0, 0.5, 0.0, 0.25]
    )
    np.testing.assert_array_equal(colors.GrayVariation(0.4)(), [0.4, 0.4, 0.4, 1.0])
    red = colors.RgbVariation(distributions.Uniform(0, 1), 0, 0)(random_state=rs(3))
    assert red[0] == rs(3).uniform(0, 1)
    assert repr(colors.GrayVariation(0.4)) == "GrayVariation(gray_level=0.4, alpha=1.0)"


def test_math_ops_apply_numpy_to_evaluated_arguments():
    pair = [deterministic.Constant(3.0), deterministic.Constant(4.0)]
    assert vmath.Norm(pair)() == 5.0
    assert vmath.Max(pair)() == 4.0 and vmath.Min(pair)() == 3.0
    assert vmath.Log(deterministic.Constant(np.e))() == pytest.approx(1.0)
    np.testing.assert_array_equal(vmath.Max(np.array([[1, 5], [3, 2]]), axis=0)(), [3, 5])
    assert vmath.Norm(pair) == vmath.Norm(pair) and vmath.Norm(pair) != vmath.Max(pair)


# -- rotations, against MuJoCo's quaternion functions --------------------------------------


def mujoco_axis_angle(axis, angle) -> np.ndarray:
    quat = np.empty(4)
    mujoco.mju_axisAngle2Quat(quat, np.asarray(axis, float), float(angle))
    return quat


def test_quaternion_from_axis_angle_matches_mujoco():
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    quat = rotations.QuaternionFromAxisAngle(axis, 0.7)()
    np.testing.assert_allclose(quat, mujoco_axis_angle(axis, 0.7), atol=1e-15)
    np.testing.assert_array_equal(
        rotations.QuaternionFromAxisAngle((0, 0, 1), 0.0)(), rotations.IDENTITY_QUATERNION
    )
    varied = rotations.QuaternionFromAxisAngle(
        (0, 0, 1), distributions.Uniform(-np.pi, np.pi, single_sample=True)
    )
    quat = varied(initial_value=np.array([1.0, 0, 0, 0]), random_state=rs(4))
    np.testing.assert_allclose(quat, mujoco_axis_angle((0, 0, 1), rs(4).uniform(-np.pi, np.pi)))


def test_pre_multiply_and_rotate_match_mujoco():
    tilt = mujoco_axis_angle((1, 0, 0), 0.3)
    start = mujoco_axis_angle((0, 1, 0), -1.1)
    expected = np.empty(4)
    mujoco.mju_mulQuat(expected, tilt, start)
    product = rotations.QuaternionPreMultiply(tilt)(initial_value=start, current_value=tilt)
    np.testing.assert_allclose(product, expected, atol=1e-15)
    cumulative = rotations.QuaternionPreMultiply(tilt, cumulative=True)
    np.testing.assert_allclose(cumulative(initial_value=tilt, current_value=start), expected)
    vector = np.array([0.2, -1.0, 3.0])
    rotated = np.empty(3)
    mujoco.mju_rotVecQuat(rotated, vector, start)
    np.testing.assert_allclose(rotations.QuaternionRotate(start, vector)(), rotated, atol=1e-14)
    from_value = rotations.QuaternionRotate(start)(initial_value=vector, current_value=None)
    np.testing.assert_allclose(from_value, rotated, atol=1e-14)


def test_uniform_quaternion_is_unit_from_three_uniform_draws():
    quats = np.array([rotations.UniformQuaternion()(random_state=rs(s)) for s in range(200)])
    np.testing.assert_allclose(np.linalg.norm(quats, axis=1), 1.0)
    u1, u2, u3 = rs(0).uniform([0.0] * 3, [1.0, 2 * np.pi, 2 * np.pi])
    np.testing.assert_allclose(
        quats[0],
        [
            np.sqrt(1 - u1) * np.sin(u2),
            np.sqrt(1 - u1) * np.cos(u2),
            np.sqrt(u1) * np.sin(u3),
            np.sqrt(u1) * np.cos(u3),
        ],
    )
    # Uniform over rotations: each component's mean is 0 and its mean square 1/4.
    np.testing.assert_allclose(np.mean(quats**2, axis=0), 0.25, atol=0.06)


# -- broadcaster ------------------------------------------------------------------------


def test_broadcaster_gives_every_proxy_the_same_values_in_rounds():
    broadcaster = variation_broadcaster.VariationBroadcaster(distributions.Uniform())
    first, second = broadcaster.get_proxy(), broadcaster.get_proxy()
    expected = rs(3).uniform(size=2)
    r = rs(3)
    assert [first(random_state=r), first(random_state=r)] == list(expected)
    assert [second(random_state=r), second(random_state=r)] == list(expected)


# -- variators ----------------------------------------------------------------------------


def test_mjcf_variator_rebinds_forgets_and_resets_initial_values():
    block = Block()
    variator = variation.MJCFVariator()
    variator.bind_attributes(block.geom, size=noises.Multiplicative(2.0))
    variator.apply_variations(rs())
    variator.apply_variations(rs())
    np.testing.assert_array_equal(block.geom.size, [0.1] * 3)  # twice the bound value
    variator.reset_initial_values()
    variator.apply_variations(rs())
    np.testing.assert_array_equal(block.geom.size, [0.2] * 3)  # twice the value then
    variator.bind_attributes(block.geom, size=noises.Additive(1.0))  # replaces
    variator.apply_variations(rs())
    np.testing.assert_array_equal(block.geom.size, [1.2] * 3)
    variator.bind_attributes(block.geom, size=None)  # forgets
    variator.apply_variations(rs())
    np.testing.assert_array_equal(block.geom.size, [1.2] * 3)


def test_mjcf_variator_evaluates_in_binding_order_with_initial_and_current_values():
    calls: list = []
    first, second = Block(name="first"), Block(name="second")
    variator = variation.MJCFVariator()
    variator.bind_attributes(second.geom, rgba=Recorder("rgba", calls))
    variator.bind_attributes(first.geom, size=Recorder("size", calls))
    variator.bind_attributes(second.geom, mass=Recorder("mass", calls))
    second.geom.mass = 0.5
    state = rs()
    with pytest.raises(composer.VariationError):  # the labels are not valid values
        variator.apply_variations(state)
    assert [c[0] for c in calls] == ["rgba", "mass", "size"]
    assert calls[1][1:] == (0.2, 0.5, state)


def test_a_failed_variation_changes_no_attribute():
    blocks = [Block(name="a"), Block(name="b")]
    variator = variation.MJCFVariator()
    variator.bind_attributes(blocks[0].geom, size=[0.3, 0.3, 0.3])
    variator.bind_attributes(blocks[1].geom, mass=2.0, size=[1, 2, 3, 4])
    with pytest.raises(composer.VariationError, match=r"<geom name=\"geom\">.*'size'"):
        variator.apply_variations(rs())
    np.testing.assert_array_equal(blocks[0].geom.size, [0.05] * 3)
    assert blocks[1].geom.mass == 0.2


def test_unknown_attributes_raise_an_attribute_error_of_ours():
    block = Block()
    with pytest.raises(AttributeError, match="cannot vary 'sizes'") as caught:
        variation.MJCFVariator().bind_attributes(block.geom, sizes=1.0)
    assert isinstance(caught.value, composer.VariationError)
    physics_variator = variation.PhysicsVariator()
    physics_variator.bind_attributes(block.body, masss=1.0)
    physics = mjcf.Physics.from_mjcf_model(block.mjcf_model)
    with pytest.raises(variation.VariationAttributeError, match="physics field 'masss'"):
        physics_variator.apply_variations(physics, rs())


def test_physics_variator_forgets_clears_and_undoes_a_failed_call():
    block = Block()
    physics = mjcf.Physics.from_mjcf_model(block.mjcf_model)
    body = physics.bind(block.body)
    variator = variation.PhysicsVariator()
    variator.bind_attributes(block.body, mass=noises.Multiplicative(3.0))
    variator.apply_variations(physics, rs())
    assert float(body.mass) == pytest.approx(0.6)
    variator.bind_attributes(block.body, mass=None)
    variator.apply_variations(physics, rs())
    assert float(body.mass) == pytest.approx(0.6)
    variator.bind_attributes(block.body, mass=1.0, pos=[1.0, 2.0])  # pos takes 3 numbers
    with pytest.raises(composer.VariationError, match="physics field 'pos'"):
        variator.apply_variations(physics, rs())
    assert float(body.mass) == pytest.approx(0.6)
    variator.clear()
    variator.apply_variations(physics, rs())
    assert float(body.mass) == pytest.approx(0.6)
