"""tasks: ready-made composer tasks, registered as Gymnasium ids on import.

    import gymnasium as gym
    import tasks                                       # registers every id below
    env = gym.make('composer/Reach-v0', flatten_observations=True)
    env = gym.make('tasks:composer/Reach-v0')          # or let gym.make import tasks
    env = gym.make('composer/CartpoleSwingup-v0', time_limit=5.0, randomize=False)

| id                               | task                                              |
| -------------------------------- | ------------------------------------------------- |
| composer/CartpoleSwingup-v0      | swing a hanging pole up and balance it            |
| composer/Reach-v0                | planar 2-link arm fingertip to a random target    |
| composer/AntRun-v0               | quadruped runs along a corridor                   |
| composer/WalkerRun-v0            | planar biped runs along a corridor                |
| composer/ArmPushBox-v0           | UR5e + Robotiq 2F-85 push a box to a target       |

Every id takes the task's constructor keywords (see each class: control_timestep,
randomize, arena options ...) and the environment's `time_limit`, `flatten_observations`,
`render_mode`, `width`, `height`, `camera_id` and `camera_name` through
`gym.make(id, **kwargs)`; `pixels=True` (with `frame_stack`, `proprioception`) observes the
task through its camera instead (`composer.pixels`): `gym.make('composer/Reach-v0',
pixels=True, width=64, height=64)`. Rewards are documented on each class;
tasks with a goal report `info['is_success']`. Every task also computes its per-step
methods and observables for many environments at once (`*_batch` twins, batchable
observables), so `gym.make_vec(id, num_envs=64, vectorization_mode='vector_entry_point')`
steps them with no per-environment work (its `per_environment` is []).
"""

from composer.registration import register
from tasks import recipes as recipes  # registers each task's training recipes
from tasks import suite  # registers the Control Suite's dm_control/... ids
from tasks.cartpole import CartpoleSwingup
from tasks.locomotion import AntRun, WalkerRun
from tasks.push import ArmPushBox
from tasks.reach import Reach

IDS = (
    register("CartpoleSwingup", "tasks.cartpole:CartpoleSwingup",
             "Swing a hanging pole up and balance it on a cart", time_limit=10.0),
    register("Reach", "tasks.reach:Reach",
             "Move a planar 2-link arm's fingertip to a random target", time_limit=3.0),
    register("AntRun", "tasks.locomotion:AntRun",
             "Run an ant-like quadruped forward along a corridor", time_limit=20.0),
    register("WalkerRun", "tasks.locomotion:WalkerRun",
             "Run a planar biped forward along a corridor", time_limit=20.0),
    register("ArmPushBox", "tasks.push:ArmPushBox",
             "Push a box into a target disc with a UR5e arm and Robotiq 2F-85 gripper",
             time_limit=8.0),
)  # fmt: skip

__all__ = ["IDS", "AntRun", "ArmPushBox", "CartpoleSwingup", "Reach", "WalkerRun", "suite"]
