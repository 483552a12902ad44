"""entities.suite: the robots of dm_control's Control Suite, built with our own API.

    from entities.suite import Cartpole
    arena.attach(Cartpole(num_poles=2))

Each domain's robot as the suite's own model file describes it (its numbers, its names, its
physics options and materials), so that attached to its world (`arenas.suite`) it compiles
to the MjModel dm_control's file compiles to, array for array (`tasks.suite` serves the
tasks; tests/tasks/suite compares both).
"""

from entities.suite.acrobot import Acrobot
from entities.suite.ball_in_cup import BallInCup
from entities.suite.cartpole import Cartpole
from entities.suite.finger import Finger
from entities.suite.materials import MATERIALS, add_materials
from entities.suite.pendulum import Pendulum
from entities.suite.point_mass import PointMass
from entities.suite.reacher import Reacher
from entities.suite.walls import add_walls

__all__ = [
    "MATERIALS",
    "Acrobot",
    "BallInCup",
    "Cartpole",
    "Finger",
    "Pendulum",
    "PointMass",
    "Reacher",
    "add_materials",
    "add_walls",
]
