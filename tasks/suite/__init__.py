"""tasks.suite: the DeepMind Control Suite on composer, equal to dm_control's, on MuJoCo 4.

    import tasks                                        # registers dm_control/... ids too
    env = gym.make('dm_control/walker-walk-v0')         # Shimmy's ids and keys
    env = tasks.suite.load('cartpole', 'swingup')       # dm_control's suite.load
    tasks.suite.BENCHMARKING, tasks.suite.ALL_TASKS     # dm_control's task lists

Robots are `entities.suite`, worlds `arenas.suite`, tasks here: dm_control's model,
observations, rewards, seeded starts, timesteps, time limits and discounts, checked against
its own code step by step (tests/tasks/suite); docs/suite.md lists the tasks.
"""

from tasks.suite import (
    acrobot,
    ball_in_cup,
    cartpole,
    cheetah,
    finger,
    fish,
    hopper,
    humanoid,
    humanoid_cmu,
    lqr,
    manipulator,
    pendulum,
    point_mass,
    quadruped,
    reacher,
    stacker,
    swimmer,
    walker,
)
from tasks.suite.registry import NAMESPACE, TASKS, SuiteEntry, find, load, register_all, tagged

ALL_TASKS = tagged(None)
BENCHMARKING = tagged("benchmarking")
EXTRA = tuple(sorted(set(ALL_TASKS) - set(BENCHMARKING)))
TASKS_BY_DOMAIN = {
    domain: tuple(name for d, name in ALL_TASKS if d == domain)
    for domain in dict.fromkeys(domain for domain, _ in ALL_TASKS)
}
IDS = register_all()

__all__ = [
    "ALL_TASKS",
    "BENCHMARKING",
    "EXTRA",
    "IDS",
    "NAMESPACE",
    "TASKS",
    "TASKS_BY_DOMAIN",
    "SuiteEntry",
    "acrobot",
    "ball_in_cup",
    "cartpole",
    "cheetah",
    "find",
    "finger",
    "fish",
    "hopper",
    "humanoid",
    "humanoid_cmu",
    "load",
    "lqr",
    "manipulator",
    "pendulum",
    "point_mass",
    "quadruped",
    "reacher",
    "stacker",
    "swimmer",
    "tagged",
    "walker",
]
