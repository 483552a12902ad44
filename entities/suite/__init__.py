"""entities.suite: the robots of dm_control's Control Suite, built with our own API.

    from entities.suite import Cartpole
    arena.attach(Cartpole(num_poles=2))      # or Cheetah(), Fish(), Hopper(), Swimmer(n_links=6)

Each domain's robot as the suite's own model file describes it (its numbers, its names, its
physics options and materials), so that attached to its world (`arenas.suite`) it compiles
to the MjModel dm_control's file compiles to, array for array (`tasks.suite` serves the
tasks; tests/tasks/suite compares both).
"""

from entities.suite.cartpole import Cartpole
from entities.suite.cheetah import Cheetah
from entities.suite.fish import Fish
from entities.suite.hopper import Hopper
from entities.suite.materials import MATERIALS, add_materials
from entities.suite.swimmer import Swimmer
from entities.suite.walker import Walker

__all__ = [
    "MATERIALS",
    "Cartpole",
    "Cheetah",
    "Fish",
    "Hopper",
    "Swimmer",
    "Walker",
    "add_materials",
]
