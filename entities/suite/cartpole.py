"""The Control Suite's cart-pole: a cart on a rail with a chain of hinged poles.

    cartpole = Cartpole(num_poles=1)
    arena.attach(cartpole)
    physics.bind(cartpole.slider).qpos            # the cart's position on the rail
    physics.bind(cartpole.hinges).qpos            # each pole's angle from upright

The numbers are the suite's (`cartpole.xml`): `Cartpole` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials


class Cartpole(composer.Entity):
    """A cart-pole of `num_poles` poles.

    The numbers are the suite's (`cartpole.xml`): a 1 kg cart on a slide joint limited to
    +-1.8 m, poles of 1 m and 0.1 kg on undamped-but-for-2e-6 hinges, a 10 N motor on the
    cart, RK4 at 10 ms, no contacts. Each pole after the first hangs from the previous one's
    tip. The cameras `fixed` and `lookatcart` move back as the chain grows.
    """

    def _build(self, name: str = "cartpole", num_poles: int = 1) -> None:
        """Make the model named `name` with `num_poles` poles (1 or more). Raises
        composer.EntityError for fewer than one."""
        if isinstance(num_poles, bool) or not isinstance(num_poles, int) or num_poles < 1:
            raise composer.EntityError(f"num_poles must be an int >= 1, got {num_poles!r}")
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.set_attributes(timestep=0.01, integrator="RK4")
        root.option.flag.set_attributes(contact="disable", energy="enable")
        add_materials(root)
        pole = root.default.add("default", dclass="pole")
        pole.joint.set_attributes(type="hinge", axis=[0, 1, 0], damping=2e-6)
        pole.geom.set_attributes(
            type="capsule", fromto=[0, 0, 0, 0, 0, 1], size=[0.045], material="self", mass=0.1
        )
        world = root.worldbody
        # One pole's cameras stand where the suite's file puts them; longer chains move
        # them back by the suite's rule.
        fixed, lookatcart = (-4, -2) if num_poles == 1 else (-1 - 2 * num_poles, -2 * num_poles)
        self.cameras = (
            world.add("camera", name="fixed", pos=[0, fixed, 1], zaxis=[0, -1, 0]),
            world.add(
                "camera", name="lookatcart", mode="targetbody", target="cart",
                pos=[0, lookatcart, 2],
            ),
        )  # fmt: skip
        for rail, y in (("rail1", 0.07), ("rail2", -0.07)):
            world.add(
                "geom", name=rail, type="capsule", pos=[0, y, 1], zaxis=[1, 0, 0],
                size=[0.02, 2], material="decoration",
            )  # fmt: skip
        self.cart = world.add("body", name="cart", pos=[0, 0, 1])
        self.slider = self.cart.add(
            "joint", name="slider", type="slide", limited=True, axis=[1, 0, 0],
            range=[-1.8, 1.8], solreflimit=[0.08, 1], damping=5e-4,
        )  # fmt: skip
        self.cart.add("geom", name="cart", type="box", size=[0.2, 0.15, 0.1], material="self",
                      mass=1)  # fmt: skip
        parent, poles, hinges = self.cart, [], []
        for index in range(1, num_poles + 1):
            position = {} if index == 1 else {"pos": [0, 0, 1]}
            body = parent.add("body", name=f"pole_{index}", childclass=pole, **position)
            hinges.append(body.add("joint", name=f"hinge_{index}"))
            body.add("geom", name=f"pole_{index}")
            poles.append(body)
            parent = body
        self.poles, self.hinges = tuple(poles), tuple(hinges)
        self.motor = root.actuator.add(
            "motor", name="slide", joint=self.slider, gear=[10], ctrllimited=True,
            ctrlrange=[-1, 1],
        )  # fmt: skip
