"""CartpoleSwingup: swing a hanging pole up and balance it, the classic benchmark.

    env = gym.make('composer/CartpoleSwingup-v0', flatten_observations=True)
    env = gym.make('composer/CartpoleSwingup-v0', start_upright=True)     # balance only

Observations (5 numbers): `cartpole/cart_position` (1), `cartpole/pole_angle` (cos, sin;
2), `cartpole/velocities` (cart, pole; 2). Action: one force on the cart in [-1, 1]
(10 N at 1). Episodes last `time_limit` (10 s: 200 steps of 0.05 s) and never terminate.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import composer
import mjcf
from arenas import Floor
from entities import CartPole
from tasks.rewards import Tolerance


class CartpoleSwingup(composer.Task):
    """Swing up and balance a cart-pole; the pole starts hanging down.

    Reward per step, in [0, 1], the product of four factors:
    `upright = (cos(angle) + 1) / 2` (1 upright, 0 hanging);
    `centered = (1 + tolerance(cart_x, margin=2)) / 2` (1 at the rail's centre, gaussian);
    `small_control = (4 + tolerance(u, margin=1, value_at_margin=0, 'quadratic')) / 5`;
    `small_velocity = (1 + tolerance(pole_angular_velocity, margin=5)) / 2`.
    A random policy returns about 23 over the 200 steps; balancing upright earns close to 1
    per step.
    """

    def __init__(
        self,
        control_timestep: float = 0.05,
        physics_timestep: float = 0.01,
        randomize: bool = True,
        start_upright: bool = False,
        pole_length: float = 1.0,
        floor_size: Sequence[float] = (4.0, 2.0),
    ) -> None:
        """Build the scene. `randomize` adds noise to the initial pole angle and cart
        position (see `initialize_episode`); `start_upright` makes it a balance task.
        Raises composer.TaskError for timesteps that do not divide."""
        self.arena = Floor(name="floor", size=floor_size, elevation=-10.0)
        self.cartpole = CartPole(pole_length=pole_length)
        self.arena.attach(self.cartpole)
        root = self.arena.mjcf_model
        root.statistic.center = [0, 0, 1.2]
        root.statistic.extent = 2.5
        for observable in self.cartpole.observables.values():
            observable.enabled = True
        self.render_camera = f"{self.cartpole.name}/track"  # follows the cart
        self.randomize = randomize
        self.start_upright = start_upright
        # The reward's terms, checked once (see the class docstring).
        self._centered = Tolerance(margin=2.0)
        self._small_control = Tolerance(margin=1.0, value_at_margin=0.0, sigmoid="quadratic")
        self._small_velocity = Tolerance(margin=5.0)
        self.set_timesteps(control_timestep, physics_timestep)

    @property
    def root_entity(self) -> composer.Entity:
        """The floor arena with the cart-pole."""
        return self.arena

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Resolve the joints' indices once."""
        joints = physics.bind([self.cartpole.slider, self.cartpole.hinge]).ids
        self._qpos = [int(i) for i in physics.model.jnt_qposadr[joints]]

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Pole hanging (or upright); with `randomize`, angle noise of sd 0.1 rad and the
        cart at x ~ U(-0.5, 0.5) (swing-up) or small noise of both (balance)."""
        cart, angle = 0.0, (0.0 if self.start_upright else np.pi)
        if self.randomize and self.start_upright:
            cart, angle = 0.01 * random_state.randn(), 0.01 * random_state.randn()
        elif self.randomize:
            cart, angle = random_state.uniform(-0.5, 0.5), np.pi + 0.1 * random_state.randn()
        qpos = physics.data.qpos
        qpos[self._qpos[0]] = cart
        qpos[self._qpos[1]] = angle

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment, shape (n,): see the class docstring."""
        slider, hinge = physics.bind(self.cartpole.slider), physics.bind(self.cartpole.hinge)
        one, two = _ONE, _TWO
        upright = (np.cos(hinge.qpos[:, 0]) + one) / two
        centered = (one + self._centered(slider.qpos[:, 0])) / two
        small_control = (_FOUR + self._small_control(physics.field("ctrl")[:, 0])) / _FIVE
        small_velocity = (one + self._small_velocity(hinge.qvel[:, 0])) / two
        return upright * centered * small_control * small_velocity


# The reward's numbers as 0-d arrays: numpy's arithmetic on small arrays takes a third less
# time with these than with Python floats, to the same result (`tasks.rewards` does the same).
_ONE, _TWO, _FOUR, _FIVE = (np.array(value) for value in (1.0, 2.0, 4.0, 5.0))
