"""Variation: distributions, their arithmetic, and MJCF/physics variators in episodes."""

from __future__ import annotations

import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from composer import variation
from tests.composer.scenes import Block


def rs(seed: int = 0) -> np.random.RandomState:
    return np.random.RandomState(seed)


@pytest.mark.parametrize(
    ("distribution", "draw"),
    [
        (variation.Uniform(-1, 2), lambda r, size: r.uniform(-1, 2, size)),
        (variation.Normal(3, 0.5), lambda r, size: r.normal(3, 0.5, size)),
        (variation.LogNormal(0, 0.2), lambda r, size: r.lognormal(0, 0.2, size)),
        (variation.Bernoulli(0.3), lambda r, size: r.binomial(1, 0.3, size)),
    ],
)
def test_distributions_draw_from_the_random_state_in_the_initial_value_shape(distribution, draw):
    assert np.array_equal(distribution(random_state=rs(1)), draw(rs(1), None))
    drawn = distribution(initial_value=np.zeros(3), random_state=rs(2))
    assert np.shape(drawn) == (3,)
    assert np.array_equal(drawn, draw(rs(2), (3,)))


def test_parameters_broadcast_and_single_sample():
    color = variation.Uniform([0, 0, 0, 1], [1, 1, 1, 1])
    drawn = color(random_state=rs())
    assert drawn.shape == (4,) and drawn[3] == 1
    one = variation.Uniform(0, 1, single_sample=True)(initial_value=np.zeros(3), random_state=rs())
    assert np.shape(one) == ()


def test_choice_picks_one_of_the_choices():
    choice = variation.Choice(["a", "b", "c"])
    picks = {choice(random_state=rs(seed)) for seed in range(20)}
    assert picks == {"a", "b", "c"}
    assert variation.Choice([1, 2], p=[0, 1])(random_state=rs()) == 2
    with pytest.raises(composer.VariationError, match="at least one"):
        variation.Choice([])


def test_arithmetic_composes_variations_and_constants():
    two = variation.Uniform(2, 2)
    assert (two * 3 + 1)(random_state=rs()) == 7
    assert (1 - two)(random_state=rs()) == -1
    assert (two / 4)(random_state=rs()) == 0.5
    assert (8 / two)(random_state=rs()) == 4
    assert (-two)(random_state=rs()) == -2
    assert (two**3)(random_state=rs()) == 8
    total = variation.Uniform(0, 1) + variation.Normal(0, 1)
    r = rs(5)
    expected = r.uniform(0, 1) + r.normal(0, 1)
    assert total(random_state=rs(5)) == expected
    assert variation.evaluate(4.0) == 4.0
    with pytest.raises(composer.VariationError, match="Uniform"):
        variation.Uniform([0, 0], [1, 1, 1])(random_state=rs())


class Doubled(variation.Variation):
    """Twice the value the attribute had when bound (or compiled)."""

    def __call__(self, initial_value=None, current_value=None, random_state=None):
        return 2 * np.asarray(initial_value)


class VariedTask(composer.Task):
    """A block whose size varies in the MJCF and whose mass varies in the physics."""

    def __init__(self, vary_mjcf: bool) -> None:
        self._arena = Floor()
        self.block = Block()
        self._arena.add_free_entity(self.block)
        self.vary_mjcf = vary_mjcf
        self.mjcf_variator = variation.MJCFVariator()
        self.mjcf_variator.bind_attributes(self.block.geom, size=variation.Uniform(0.02, 0.1))
        self.physics_variator = variation.PhysicsVariator()
        self.physics_variator.bind_attributes(self.block.body, mass=Doubled())
        self.compiles = 0

    @property
    def root_entity(self):
        return self._arena

    def initialize_episode_mjcf(self, random_state):
        if self.vary_mjcf:
            self.mjcf_variator.apply_variations(random_state)

    def after_compile(self, physics, random_state):
        self.compiles += 1

    def initialize_episode(self, physics, random_state):
        self.physics_variator.apply_variations(physics, random_state)

    def get_reward(self, physics):
        return 0.0


def test_mjcf_variator_changes_the_model_each_episode_and_recompiles():
    task = VariedTask(vary_mjcf=True)
    env = composer.Environment(task)
    sizes = []
    for seed in range(3):
        env.reset(seed=seed)
        sizes.append(env.physics.bind(task.block.geom).size.copy())
        np.testing.assert_array_equal(sizes[-1], task.block.geom.size)
    assert task.compiles == 4  # construction + each episode
    assert len({s.tobytes() for s in sizes}) == 3
    assert all(((s >= 0.02) & (s <= 0.1)).all() for s in sizes)


def test_physics_variator_uses_the_compiled_value_as_initial_and_does_not_recompile():
    task = VariedTask(vary_mjcf=False)
    env = composer.Environment(task)
    body = env.physics.bind(task.block.body)
    compiled_mass = float(body.mass)
    for seed in range(3):
        env.reset(seed=seed)
        assert float(body.mass) == pytest.approx(2 * compiled_mass)  # not 4x, 8x
    assert task.compiles == 1


def test_variators_name_the_element_and_attribute_on_bad_input():
    block = Block()
    variator = variation.MJCFVariator()
    with pytest.raises(composer.VariationError, match="cannot vary 'sizes'"):
        variator.bind_attributes(block.geom, sizes=variation.Uniform())
    five = variation.Uniform(np.zeros(5), np.ones(5), single_sample=True)
    variator.bind_attributes(block.geom, size=five)  # a geom size has 1 to 3 numbers
    with pytest.raises(composer.VariationError, match=r"<geom name=\"geom\">.*'size'"):
        variator.apply_variations(rs())
    physics_variator = variation.PhysicsVariator()
    physics_variator.bind_attributes(block.body, masss=1.0)
    physics = mjcf.Physics.from_mjcf_model(block.mjcf_model)
    with pytest.raises(composer.VariationError, match="physics field 'masss'"):
        physics_variator.apply_variations(physics, rs())
