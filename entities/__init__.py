"""entities: robots and props to compose into scenes.

    import entities
    arm = entities.PlanarArm(link_lengths=(0.12, 0.12))    # also CartPole, Quadruped, Walker
    box = entities.Box(half_sizes=(0.03, 0.03, 0.03), mass=0.1, rgba=(1, 0, 0, 1))
    robot = entities.robots.ur5e_with_2f85()              # real robot files: arm + gripper

Each is a `composer.Entity` owning its MJCF model: its joints, sites and bodies are
attributes, its observables disabled until a task enables them, its actuators the action (in
[-1, 1] for the hand-made robots, real ones' own ctrlrange). Errors: `composer.EntityError`.
"""

from entities import robots
from entities.cartpole import CartPole
from entities.features import Clipped, HingeAngles
from entities.planar_arm import PlanarArm
from entities.props import Box, Capsule, Cylinder, MeshProp, Prop, PropError, Sphere
from entities.quadruped import Quadruped
from entities.walker import Walker

__all__ = [
    "Box",
    "Capsule",
    "CartPole",
    "Clipped",
    "Cylinder",
    "HingeAngles",
    "MeshProp",
    "PlanarArm",
    "Prop",
    "PropError",
    "Quadruped",
    "Sphere",
    "Walker",
    "robots",
]
