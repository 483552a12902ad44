"""entities.suite: the robots of dm_control's Control Suite, built with our own API.

    from entities.suite import Cartpole
    arena.attach(Cartpole(num_poles=2))      # or Cheetah(), Fish(), Hopper(), Swimmer(n_links=6)

Each domain's robot as the suite's own model file describes it (its numbers, its names, its
physics options and materials), so that attached to its world (`arenas.suite`) it compiles
to the MjModel dm_control's file compiles to, array for array (`tasks.suite` serves the
tasks; tests/tasks/suite compares both).
"""

from entities.suite.acrobot import Acrobot
from entities.suite.ball_in_cup import BallInCup
from entities.suite.cartpole import Cartpole
from entities.suite.cheetah import Cheetah
from entities.suite.finger import Finger
from entities.suite.fish import Fish
from entities.suite.hopper import Hopper
from entities.suite.humanoid import Humanoid
from entities.suite.humanoid_cmu import HumanoidCMU
from entities.suite.lqr import LQR
from entities.suite.manipulator import Manipulator
from entities.suite.materials import MATERIALS, add_materials
from entities.suite.pendulum import Pendulum
from entities.suite.planar_arm import PlanarArm, add_planar_arm
from entities.suite.point_mass import PointMass
from entities.suite.quadruped import Quadruped
from entities.suite.reacher import Reacher
from entities.suite.stacker import Stacker
from entities.suite.swimmer import Swimmer
from entities.suite.walker import Walker
from entities.suite.walls import add_walls

__all__ = [
    "LQR",
    "MATERIALS",
    "Acrobot",
    "BallInCup",
    "Cartpole",
    "Cheetah",
    "Finger",
    "Fish",
    "Hopper",
    "Humanoid",
    "HumanoidCMU",
    "Manipulator",
    "Pendulum",
    "PlanarArm",
    "PointMass",
    "Quadruped",
    "Reacher",
    "Stacker",
    "Swimmer",
    "Walker",
    "add_materials",
    "add_planar_arm",
    "add_walls",
]
