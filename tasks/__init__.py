"""tasks: ready-made composer tasks, registered as Gymnasium ids on import.

    import tasks                        # registers IDS (composer/...) and the dm_control/... ids
    env = gym.make('composer/Reach-v0', flatten_observations=True)   # or 'tasks:composer/...'
    env = gym.make('composer/CartpoleSwingup-v0', randomize=False, time_limit=5.0, pixels=True)

`gym.make` takes the task's keywords and the environment's (the README's "Tasks" lists both
and the ids); rewards are on each class; goal tasks report `info['is_success']`. Every task
is batched: `gym.make_vec(id, num_envs=64, vectorization_mode='vector_entry_point')` steps
it with no per-environment work (its `per_environment` is []).
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
