"""A cart-pole: a cart sliding on a rail with a pole hinged on top, one force on the cart.

    cartpole = CartPole(pole_length=1.0)
    arena.attach(cartpole)
    cartpole.observables.pole_angle.enabled = True      # (cos, sin) of the pole angle
    physics.bind(cartpole.hinge).qpos = np.pi           # hanging down; 0 is upright

The rail runs along world x at `height`; the pole angle is 0 upright and grows
counter-clockwise seen from -y. Cart and pole touch nothing (the pole passes through the
floor when hanging low), so the dynamics are those of the classic benchmark.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from composer import observation
from entities.features import Clipped, HingeAngles, velocities


class CartPole(composer.Entity):
    """A cart on a rail (joint `slider`) with a pole on a hinge (joint `hinge`); the one
    actuator pushes the cart with force `gear * control`, control in [-1, 1]; the camera
    `track` follows the cart."""

    def _build(
        self,
        name: str = "cartpole",
        pole_length: float = 1.0,
        pole_mass: float = 0.1,
        cart_mass: float = 1.0,
        rail_half_length: float = 2.0,
        height: float = 1.2,
        gear: float = 10.0,
    ) -> None:
        """Make the cart-pole model named `name`: rail limits +-`rail_half_length` m, cart
        and pole masses in kg, maximum force `gear` N."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.compiler.angle = "radian"
        root.default.geom.set_attributes(contype=0, conaffinity=0)
        root.asset.add("material", name="self", rgba=[0.7, 0.5, 0.3, 1])
        root.asset.add("material", name="rail", rgba=[0.3, 0.3, 0.35, 1])
        root.worldbody.add(
            "geom", name="rail", type="capsule", size=[0.02], material="rail",
            fromto=[-rail_half_length - 0.2, 0, height, rail_half_length + 0.2, 0, height],
        )  # fmt: skip
        cart = root.worldbody.add("body", name="cart", pos=[0, 0, height])
        self.slider = cart.add(
            "joint", name="slider", type="slide", axis=[1, 0, 0], limited=True,
            range=[-rail_half_length, rail_half_length], damping=5e-4,
        )  # fmt: skip
        cart.add("geom", name="cart", type="box", size=[0.2, 0.15, 0.1], mass=cart_mass,
                 material="self")  # fmt: skip
        pole = cart.add("body", name="pole", pos=[0, -0.16, 0])
        self.hinge = pole.add("joint", name="hinge", type="hinge", axis=[0, 1, 0], damping=2e-6)
        pole.add(
            "geom", name="pole", type="capsule", fromto=[0, 0, 0, 0, 0, pole_length],
            size=[0.045], mass=pole_mass, material="self",
        )  # fmt: skip
        self.pole_tip = pole.add("site", name="tip", pos=[0, 0, pole_length], size=[0.01])
        # Follows the cart along the rail (mode "track": its offset from the cart stays
        # fixed in the world), far enough back for the pole upright and hanging.
        distance = 1.5 + 2.5 * pole_length
        self.camera = cart.add(
            "camera", name="track", mode="track", pos=[0, -distance, 0.1 * distance],
            xyaxes=[1, 0, 0, 0, 0.1, 1],
        )  # fmt: skip
        self.cart = cart
        self.pole = pole
        root.actuator.add(
            "motor", name="slide", joint=self.slider, gear=[gear], ctrllimited=True,
            ctrlrange=[-1, 1],
        )  # fmt: skip

    @composer.observable
    def cart_position(self) -> observation.Observable:
        """The cart's position along the rail (m), shape (1,)."""
        limit = float(self.slider.range[1]) + 0.5
        return Clipped("qpos", [self.slider], -limit, limit)

    @composer.observable
    def pole_angle(self) -> observation.Observable:
        """(cos, sin) of the pole angle; (1, 0) upright."""
        return HingeAngles([self.hinge])

    @composer.observable
    def velocities(self) -> observation.Observable:
        """(cart velocity m/s, pole angular velocity rad/s)."""
        return velocities([self.slider, self.hinge])

    def pole_angle_cosine(self, physics: mjcf.Physics) -> float:
        """cos of the pole angle: 1 upright, -1 hanging."""
        return float(np.cos(physics.bind(self.hinge).qpos[0]))
