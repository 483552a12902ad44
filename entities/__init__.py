"""entities: robots and props to compose into scenes.

    import entities
    from entities import robots
    cartpole = entities.CartPole()
    arm = entities.PlanarArm(link_lengths=(0.12, 0.12))        # fingertip site: arm.fingertip
    ant, walker = entities.Quadruped(), entities.Walker()
    box = entities.Box(half_sizes=(0.03, 0.03, 0.03), mass=0.1, rgba=(1, 0, 0, 1))
    mug = entities.MeshProp('mug.stl', scale=0.001, free=True)
    ur5e = robots.from_menagerie('universal_robots_ur5e')     # real robot files
    robot = robots.ur5e_with_2f85()                           # arm + gripper

Every entity is a `composer.Entity`: it owns its MJCF model, names its joints, sites and
bodies as attributes, declares observables (disabled until a task enables them) and its
actuators are the action (controls in [-1, 1] for the hand-made robots; the files' own
ctrlrange for real robots). Errors are `composer.EntityError` subclasses.
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
