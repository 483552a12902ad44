"""The silent differences from dm_control's Composer that issue 25 found (each failed on the
main branch before it): randomness outside the environment's seed, and entities attached
somewhere else than their parent's `attachment_site`."""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas import Floor
from composer import observation, variation
from tests.composer.scenes import Block, Pendulum


class AdditiveNoise:
    """A corruptor as dm_control's noises are: a Variation called `(initial_value,
    current_value, random_state)`, corruptors by `corruptor(value, random_state=...)`, and
    numpy's global generator when no random state is given."""

    def __call__(self, initial_value=None, current_value=None, random_state=None):
        random_state = np.random if random_state is None else random_state
        return initial_value + random_state.normal(0.0, 0.1, size=np.shape(initial_value))


class NoisyTask(composer.Task):
    """Every kind of draw the framework makes or passes on: a corruptor, a prop placer, a
    hook's own draw."""

    def __init__(self):
        self._arena = Floor(size=(2, 2))
        self.pendulum = Pendulum()
        self._arena.attach(self.pendulum)
        self.block = Block()
        self._arena.add_free_entity(self.block)
        self.pendulum.joint_positions.enabled = True
        self.pendulum.joint_positions.corruptor = AdditiveNoise()
        self._placer = composer.initializers.PropPlacer(
            [self.block], position=variation.Uniform([0.5, 0.5, 0.06], [1.0, 1.0, 0.2])
        )
        self.set_timesteps(control_timestep=0.02, physics_timestep=0.005)

    @property
    def root_entity(self):
        return self._arena

    @property
    def task_observables(self):
        block = self.block
        position = observation.Generic(lambda physics: block.get_pose(physics)[0])
        position.enabled = True
        return {"block_position": position}

    def initialize_episode(self, physics, random_state):
        physics.bind(self.pendulum.hinge).qpos = random_state.uniform(-1, 1)
        self._placer(physics, random_state)

    def get_reward(self, physics):
        return 0.0


def _rollout(make_env, global_seed: int) -> list:
    env = make_env()
    np.random.seed(global_seed)
    observations = [env.reset(seed=3)[0]]
    actions = np.linspace(-1, 1, 5)
    for action in actions:
        np.random.seed(global_seed + 100)  # as if other code drew between steps
        observations.append(env.step(np.full(env.action_space.shape, action))[0])
    observations.append(env.reset()[0])  # an unseeded reset continues the seeded state
    env.close()
    return observations


def _assert_same(first: list, second: list) -> None:
    for one, other in zip(first, second, strict=True):
        assert one.keys() == other.keys()
        for key in one:
            np.testing.assert_array_equal(one[key], other[key], err_msg=key)


def test_numpy_global_seed_changes_nothing_in_an_environment():
    first = _rollout(lambda: composer.Environment(NoisyTask()), global_seed=1)
    second = _rollout(lambda: composer.Environment(NoisyTask()), global_seed=2)
    _assert_same(first, second)
    noisy = np.array([obs["pendulum/joint_positions"][0] for obs in first])
    assert np.unique(noisy).size == noisy.size  # the corruptor did draw


def test_numpy_global_seed_changes_nothing_in_a_vector_environment():
    def make():
        return composer.VectorEnvironment(NoisyTask, num_envs=2)

    first = _rollout(make, global_seed=1)
    second = _rollout(make, global_seed=2)
    _assert_same(first, second)


def test_corruptors_are_called_with_the_random_state_by_keyword():
    seen = []

    def corruptor(value, *, random_state):  # keyword only, as dm_control passes it
        seen.append(random_state)
        return value

    task = NoisyTask()
    task.pendulum.joint_positions.corruptor = corruptor
    env = composer.Environment(task)
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape))
    assert seen and all(state is env.random_state for state in seen)


class Arm(composer.Entity):
    """An arm whose wrist is where things mount, as dm_control's arms say."""

    def _build(self):
        root = self._mjcf_root = mjcf.RootElement(model="arm")
        body = root.worldbody.add("body", name="upper", pos=[0, 0, 1])
        body.add("geom", type="capsule", fromto=[0, 0, 0, 0.5, 0, 0], size=[0.05])
        self.wrist = body.add("site", name="wrist", pos=[0.5, 0, 0])

    @property
    def attachment_site(self):
        return self.wrist


def test_attach_without_a_site_mounts_at_the_attachment_site():
    arena, arm, hand = Floor(), Arm(), Pendulum("hand")
    arena.attach(arm)
    frame = arm.attach(hand)  # no site: the arm's wrist
    assert frame.parent is arm.wrist.parent
    np.testing.assert_array_equal(frame.pos, arm.wrist.pos)
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    np.testing.assert_allclose(physics.bind(hand.mjcf_model.find("body", "base")).xpos,
                               [0.5, 0, 2])  # fmt: skip
    # The default is the model's root: its world body.
    frame = Pendulum("other").attach(Block())
    assert frame.parent.tag == "worldbody"
