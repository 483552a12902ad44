"""Every Control Suite task here against dm_control's own (issue 38): the same MjModel, and
from the same seed and the same 1,000 actions the same observations, rewards, discounts and
episode ends, to 1e-9 (`tests/tasks/suite/oracle.py` runs dm_control's suite code, from
its published wheel, on our mjcf.Physics). Then what a Gymnasium user relies on: the ids,
`check_env`, flattening in dm_control's key order, vector environments equal to single
ones, and clear errors."""

from __future__ import annotations

import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import composer
import tasks  # noqa: F401  (registers the ids)
from composer import registration
from tasks import suite
from tests.tasks.suite import oracle
from tests.vector_runs import assert_same_runs

ALL = [pytest.param(domain, task, id=f"{domain}-{task}") for domain, task in suite.ALL_TASKS]
STEPS = 1000


def _seed(domain: str, task: str) -> int:
    """A seed of its own for each task (stable across runs)."""
    return sum(map(ord, f"{domain}/{task}")) % 1000


# Domains whose model dm_control draws from the task's seed (lqr's springs), which ours
# draws at a seeded reset: their models are compared after one.
DRAWN_MODELS = {"lqr"}


@pytest.mark.parametrize(("domain", "task"), ALL)
def test_the_model_is_dm_control_s_array_for_array(domain, task):
    ours = suite.load(domain, task)
    theirs = oracle.reference(domain, task, seed=0)
    if domain in DRAWN_MODELS:
        ours.reset(seed=0)
    oracle.assert_same_model(ours.physics.model, theirs.physics.model)


@pytest.mark.parametrize(("domain", "task"), ALL)
def test_an_episode_is_dm_control_s_step_for_step(domain, task):
    seed = _seed(domain, task)
    ours = suite.load(domain, task)
    theirs = oracle.reference(domain, task, seed=seed)
    assert ours.control_timestep == pytest.approx(theirs.control_timestep(), abs=1e-12)
    oracle.compare_episode(ours, theirs, seed=seed, steps=STEPS)


# Tasks whose reward a random policy leaves at 0 nearly throughout (it falls at once): their
# reward is compared on states near the upright pose, with random velocities and controls.
NEAR_UPRIGHT = [pytest.param(*name.split("-"), id=name) for name in ("hopper-stand", "hopper-hop")]


@pytest.mark.parametrize(("domain", "task"), NEAR_UPRIGHT)
def test_the_reward_near_upright_is_dm_control_s(domain, task):
    ours = suite.load(domain, task)
    theirs = oracle.reference(domain, task, seed=0)
    ours.reset(seed=0)
    theirs.reset()
    model, random = ours.physics.model, np.random.RandomState(5)
    rewards = []
    for _ in range(20):
        qpos = model.qpos0 + 0.1 * random.randn(model.nq)
        qvel, ctrl = random.uniform(-4, 4, model.nv), random.uniform(-1, 1, model.nu)
        for physics in (ours.physics, theirs.physics):
            physics.data.qpos[:], physics.data.qvel[:], physics.data.ctrl[:] = qpos, qvel, ctrl
            physics.forward()
        rewards.append(ours.task.get_reward(ours.physics))
        assert rewards[-1] == theirs.task.get_reward(theirs.physics)
    assert len(set(rewards) - {0.0, 1.0}) >= 5  # the formula varies over these states


def test_the_fish_s_reward_near_the_target_is_dm_control_s():
    # A random policy's fish never comes near the target: its in_target term stays below
    # 1e-9. Here the target is placed near the mouth, in both simulations alike.
    ours, theirs = suite.load("fish", "swim"), oracle.reference("fish", "swim", seed=0)
    ours.reset(seed=0)
    theirs.reset()
    target = ours.physics.bind(ours.task.fish.target)
    random, rewards = np.random.RandomState(2), []
    for _ in range(20):
        mouth = ours.physics.bind(ours.task.fish.mouth).xpos.copy()
        place = mouth + random.uniform(-0.15, 0.15, 3)
        target.pos = place
        theirs.physics.named.model.geom_pos["target"] = place
        theirs.physics.forward()
        rewards.append(ours.task.get_reward(ours.physics))
        assert rewards[-1] == theirs.task.get_reward(theirs.physics)
        np.testing.assert_array_equal(
            ours.task.task_observables["target"].batch_function(ours.batch_physics)[0],
            theirs.task.get_observation(theirs.physics)["target"],
        )
    assert min(rewards) < 0.2 and max(rewards) > 0.8  # in_target spans its range


@pytest.mark.parametrize(("domain", "task"), ALL)
def test_flattened_observations_follow_dm_control_s_key_order(domain, task):
    seed = _seed(domain, task)
    ours = suite.load(domain, task, environment_kwargs={"flat_observation": True})
    flat = {"flat_observation": True}
    theirs = oracle.reference(domain, task, seed=seed, environment_kwargs=flat)
    flat, _ = ours.reset(seed=seed)
    np.testing.assert_allclose(flat, theirs.reset().observation["observations"], atol=1e-12)
    assert ours.observation_space.shape == flat.shape


@pytest.mark.parametrize("env_id", suite.IDS)
def test_every_id_passes_gymnasium_s_checks(env_id):
    with warnings.catch_warnings():
        # dm_control's observation specs are unbounded, and so are these Boxes, as Shimmy's.
        warnings.filterwarnings("ignore", ".*A Box observation space (minimum|maximum) value")
        # Asymmetric or unbounded action ranges, as dm_control's specs have them: the
        # quadruped's [-1, 1.1] and [-0.8, 0.8], lqr's unbounded motors.
        warnings.filterwarnings("ignore", ".*symmetric and normalized")
        env = gymnasium.make(env_id)
        check_env(env.unwrapped)
    observation, _ = env.reset(seed=1)
    domain, task = env_id.removeprefix("dm_control/").removesuffix("-v0").split("-")
    assert list(observation) == list(oracle.reference(domain, task, seed=1).reset().observation)
    env.close()


@pytest.mark.parametrize("domain", list(suite.TASKS_BY_DOMAIN))
def test_the_lists_are_dm_control_s(domain):
    module = oracle.suite_module(domain)  # the package's own lists need every domain
    assert list(module.SUITE) == list(suite.TASKS_BY_DOMAIN[domain])
    for tag in ("benchmarking", "easy", "hard", "no_reward_visualization"):
        ours = {
            task for task in suite.TASKS_BY_DOMAIN[domain] if tag in suite.find(domain, task).tags
        }
        assert set(module.SUITE.tagged(tag)) == ours, tag
    assert all(env_id.startswith("dm_control/") for env_id in suite.IDS)


@pytest.mark.parametrize(("domain", "task"), ALL)
def test_the_model_after_a_reset_is_dm_control_s(domain, task):
    # What the tasks change in the model each episode (a target's place and size, the
    # spinner's damping, hidden sites, tendon gains) is changed alike.
    seed = _seed(domain, task)
    ours = suite.load(domain, task)
    theirs = oracle.reference(domain, task, seed=seed)
    ours.reset(seed=seed)
    theirs.reset()
    oracle.assert_same_model(ours.physics.model, theirs.physics.model)


@pytest.mark.parametrize("n_links", [3, 8])
def test_a_swimmer_of_any_length_is_dm_control_s_model(n_links):
    # dm_control's code writes the swimmer's model for any length (`swimmer(n_links)`).
    ours = suite.load("swimmer", "swimmer6", task_kwargs={"n_links": n_links})
    theirs = oracle.reference_model("swimmer", n_joints=n_links)
    oracle.assert_same_model(ours.physics.model, theirs)


def _write(*writes):
    """A setup writing each `(field, name, value)` through a physics' named access
    (`field` as 'data.qpos'; `name` without the robot's scope), then forwarding."""

    def setup(physics, scope):
        for field, name, value in writes:
            section, array = field.split(".")
            getattr(getattr(physics.named, section), array)[scope + name] = value
        physics.forward()

    return setup


def _move_onto(kind, target, place):
    """A setup moving model `kind` (geom or site) `target` onto `place`'s current x and y
    (a geom) or x and z (a site), then forwarding."""
    axes = [0, 1] if kind == "geom" else [0, 2]

    def setup(physics, scope):
        positions = getattr(physics.named.model, f"{kind}_pos")
        position = positions[scope + target].copy()
        position[axes] = getattr(physics.named.data, f"{kind}_xpos")[scope + place][axes]
        positions[scope + target] = position
        physics.forward()

    return setup


# A state from which each task earns its reward (the random episodes above earn the sparse
# ones rarely, if ever), set alike in both simulations after a reset: by domain, or by
# 'domain-task' where a task differs.
_EARNING = {
    "cartpole": _write(("data.qpos", "slider", 0.0), ("data.qpos", "hinge_1", 0.0)),
    "pendulum": _write(("data.qpos", "hinge", 0.0)),
    "acrobot": _write(("data.qpos", "shoulder", 0.0), ("data.qpos", "elbow", 0.0)),
    "point_mass": _write(("data.qpos", "root_x", 0.0), ("data.qpos", "root_y", 0.0)),
    "reacher": _move_onto("geom", "target", "finger"),
    "finger-spin": _write(("data.qvel", "hinge", -30.0)),
    "finger": _move_onto("site", "target", "tip"),
    "ball_in_cup": _write(
        *(("data.qpos", joint, 0.0) for joint in ("cup_x", "cup_z", "ball_x")),
        ("data.qpos", "ball_z", 0.35),  # the ball's centre on the cup's inside's
        ("data.qvel", "ball_x", 0.0), ("data.qvel", "ball_z", 0.0),
    ),
}  # fmt: skip
EARNING = [
    pytest.param(domain, task, id=f"{domain}-{task}")
    for domain, task in suite.ALL_TASKS
    if domain in _EARNING or f"{domain}-{task}" in _EARNING
]


@pytest.mark.parametrize(("domain", "task"), EARNING)
def test_rewards_where_earned_are_dm_control_s(domain, task):
    seed = _seed(domain, task)
    ours = suite.load(domain, task)
    theirs = oracle.reference(domain, task, seed=seed)
    ours.reset(seed=seed)
    theirs.reset()
    earn = _EARNING.get(f"{domain}-{task}", _EARNING.get(domain))
    earn(ours.physics, f"{domain}/")  # our names carry the robot's scope
    earn(theirs.physics, "")
    rewards = oracle.compare_steps(ours, theirs, oracle.random_actions(theirs, seed, steps=50))
    assert rewards[0] > 0.5  # earned at first, compared as the state moves on


# One task of each domain whose step differs from the others' (its reward, observables).
VECTOR = [
    "cartpole-swingup",
    "cheetah-run",
    "fish-swim",
    "hopper-stand",
    "swimmer-swimmer6",
    "walker-walk",
    "pendulum-swingup",
    "acrobot-swingup",
    "point_mass-hard",
    "reacher-hard",
    "finger-spin",
    "finger-turn_hard",
    "ball_in_cup-catch",
]


@pytest.mark.parametrize("name", VECTOR)
def test_the_vector_environment_equals_single_ones(name):
    env_id = f"dm_control/{name}-v0"
    vector = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    reference = gymnasium.make_vec(env_id, num_envs=3, vectorization_mode="sync")
    assert_same_runs(vector, reference, steps=30, seed=4)
    assert vector.unwrapped.per_environment == []  # the suite's step is batched throughout
    vector.close()
    reference.close()


def test_reset_seed_is_dm_control_s_random_argument():
    env = suite.load("cartpole", "balance")
    first, _ = env.reset(seed=11)
    again, _ = env.reset(seed=11)
    np.testing.assert_array_equal(first["position"], again["position"])
    theirs = oracle.reference("cartpole", "balance", seed=11).reset().observation
    np.testing.assert_array_equal(first["position"], theirs["position"])


def test_unknown_domains_tasks_and_keywords_are_named():
    with pytest.raises(composer.TaskError, match=r"no domain 'cartpol'.*'cartpole'"):
        suite.load("cartpol", "swingup")
    with pytest.raises(composer.TaskError, match=r"no task 'swing'.*'swingup'"):
        suite.load("cartpole", "swing")
    with pytest.raises(composer.TaskError, match="n_sub_steps"):
        suite.load("cartpole", "swingup", environment_kwargs={"n_sub_steps": 2})
    with pytest.raises(registration.RegistrationError, match="num_pole"):
        gymnasium.make("dm_control/cartpole-swingup-v0", num_pole=2)


def test_bad_task_keywords_are_named():
    with pytest.raises(composer.EntityError, match="n_links must be an int >= 3, got 2"):
        gymnasium.make("dm_control/swimmer-swimmer6-v0", n_links=2)
    with pytest.raises(composer.TaskError, match="move_speed must be a number >= 0, got -1"):
        suite.load("walker", "walk", task_kwargs={"move_speed": -1})


def test_a_bad_reacher_target_size_is_named():
    with pytest.raises(composer.TaskError, match="target_size must be a positive number"):
        suite.load("reacher", "easy", task_kwargs={"target_size": -0.05})


def test_a_bad_finger_target_radius_is_named():
    with pytest.raises(composer.TaskError, match="target_radius must be a positive number"):
        gymnasium.make("dm_control/finger-turn_easy-v0", target_radius="big")


def test_bad_actions_are_refused_before_the_step():
    env = gymnasium.make("dm_control/cartpole-swingup-v0")
    env.reset(seed=0)
    with pytest.raises(composer.EpisodeError, match="shape"):
        env.step(np.zeros(2))
    with pytest.raises(composer.EpisodeError, match="non-finite"):
        env.step(np.array([np.nan]))
    env.close()


def test_another_package_s_id_is_replaced_with_a_warning():
    env_id = "dm_control/cartpole-swingup-v0"
    spec = gymnasium.registry[env_id]
    del gymnasium.registry[env_id]
    gymnasium.register(env_id, entry_point="shimmy.dm_control_compatibility:x")
    try:
        with pytest.warns(registration.RegistrationWarning, match="shimmy"):
            registration.register(
                "cartpole-swingup", "tasks.suite.cartpole:Balance", "", namespace="dm_control",
                swing_up=True,
            )  # fmt: skip
        assert gymnasium.registry[env_id].entry_point == registration.ENTRY_POINT
    finally:
        gymnasium.registry[env_id] = spec


@pytest.mark.parametrize(("domain", "task"), ALL)
def test_the_dm_env_bridge_serves_dm_control_s_specs(domain, task):
    dm_env_bridge = pytest.importorskip("composer.dm_env_bridge")
    ours = dm_env_bridge.DmEnvAdapter(suite.load(domain, task), seed=0)
    theirs = oracle.reference(domain, task, seed=0)
    mine, reference_spec = ours.action_spec(), theirs.action_spec()
    assert (mine.shape, mine.dtype) == (reference_spec.shape, reference_spec.dtype)
    np.testing.assert_array_equal(mine.minimum, reference_spec.minimum)
    np.testing.assert_array_equal(mine.maximum, reference_spec.maximum)
    observed, expected = ours.observation_spec(), theirs.observation_spec()
    assert list(observed) == list(expected)  # dm_control's order
    for key, spec in expected.items():
        assert (observed[key].shape, observed[key].dtype) == (spec.shape, spec.dtype), key


def test_pixels_are_84_pixel_frames_of_the_first_camera():
    env = gymnasium.make("dm_control/cartpole-swingup-v0", pixels=True)
    frame, _ = env.reset(seed=0)
    assert frame.shape == (84, 84, 3) and frame.dtype == np.uint8
    np.testing.assert_array_equal(frame, env.unwrapped.physics.render(84, 84, camera_id=0))
    env.close()


@pytest.mark.parametrize(
    "env_id",
    [
        "dm_control/humanoid-walk-v0",
        "dm_control/quadruped-escape-v0",
        "dm_control/quadruped-fetch-v0",
    ],
)
def test_a_free_robot_s_vector_environment_equals_single_ones(env_id):
    # Free robots whose episodes start by searching for a pose without contacts, each
    # environment its own (escape: on a terrain of its own, so their models differ), and
    # the batched step still needs no per-environment call.
    vector = gymnasium.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    reference = gymnasium.make_vec(env_id, num_envs=2, vectorization_mode="sync")
    assert_same_runs(vector, reference, steps=20, seed=5)
    assert vector.unwrapped.per_environment == []
    vector.close()
    reference.close()


def test_a_speed_out_of_range_is_refused():
    with pytest.raises(composer.TaskError, match="move_speed must be >= 0"):
        gymnasium.make("dm_control/humanoid-walk-v0", move_speed=-1.0)
    with pytest.raises(composer.TaskError, match="desired_speed must be > 0"):
        gymnasium.make("dm_control/quadruped-walk-v0", desired_speed=0.0)


def test_the_escape_terrain_is_dm_control_s_and_drawn_anew_each_episode():
    env = suite.load("quadruped", "escape")
    frames = {}
    for seed in (3, 4):
        env.reset(seed=seed)
        theirs = oracle.reference("quadruped", "escape", seed=seed)
        theirs.reset()
        np.testing.assert_array_equal(
            env.physics.model.hfield_data, theirs.physics.model.hfield_data
        )
        frames[seed] = env.physics.render(48, 48, camera_id="global")
    fresh = suite.load("quadruped", "escape")
    fresh.reset(seed=4)
    # A renderer holds the heightfield it was made with: the second episode's frame shows
    # the second terrain, not the first one's.
    np.testing.assert_array_equal(frames[4], fresh.physics.render(48, 48, camera_id="global"))
    assert not np.array_equal(frames[3], frames[4])
