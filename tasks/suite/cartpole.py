"""Cartpole: swing up and balance one or more poles on a cart (dm_control's `cartpole`).

    env = gym.make('dm_control/cartpole-swingup-v0')
    env = gym.make('dm_control/cartpole-three_poles-v0', flatten_observations=True)

Observations: `position` (the cart's position, then each pole's cos and sin of its angle
from upright), `velocity` (every joint's). Reward in [0, 1]: dense, `upright * centered *
small_control * small_velocity`; sparse, 1 while the cart is within 0.25 m of the centre
and every pole within 0.995 of upright. Swing-up starts hanging down, balance near
upright; 1,000 steps of 10 ms (details in docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from entities.suite import Cartpole
from tasks.rewards import ColumnTolerance, Tolerance, row_means
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField, Concatenated

TIME_LIMIT = 10.0
_CART_RANGE = (-0.25, 0.25)
_ANGLE_COSINE_RANGE = (0.995, 1.0)
# dm_control's tolerance terms, each built once (a call is then its arithmetic alone).
_CART_IN_BOUNDS = Tolerance(_CART_RANGE)
_ANGLE_IN_BOUNDS = Tolerance(_ANGLE_COSINE_RANGE)
_CENTERED = Tolerance(margin=2)
_SMALL_CONTROL = Tolerance(margin=1, value_at_margin=0, sigmoid="quadratic")
_SMALL_VELOCITY = Tolerance(margin=5)
_ZZ_XZ = [8, 2]  # the entries of a pole's xmat observed: its cos and sin
# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_ONE, _TWO, _FOUR, _FIVE = (np.array(value) for value in (1.0, 2.0, 4.0, 5.0))


class Balance(SuiteTask):
    """Balance (or swing up and balance) the poles of a cart-pole (module docstring)."""

    def __init__(
        self,
        swing_up: bool = False,
        sparse: bool = False,
        num_poles: int = 1,
        control_timestep: float | None = None,
    ) -> None:
        """Build the scene: `num_poles` poles, starting hanging down with `swing_up`,
        rewarded sparsely with `sparse`. Raises composer.TaskError for a control timestep
        that is not a multiple of 10 ms, composer.EntityError for fewer than one pole."""
        self.cartpole = Cartpole(num_poles=num_poles)
        self._arena = SuiteArena(floor_pos=(0.0, 0.0, 1 - num_poles - 0.05))
        self._arena.add_light(name="light", pos=[0, 0, 6])
        self._arena.attach(self.cartpole)
        self._swing_up = bool(swing_up)
        self._sparse = bool(sparse)
        self._single_pole = num_poles == 1
        # centered's gaussian and each pole's small_velocity's, computed together over
        # the cart's position and the poles' angular velocities.
        self._joints = (self.cartpole.slider, *self.cartpole.hinges)
        self._gaussians = ColumnTolerance([_CENTERED] + [_SMALL_VELOCITY] * num_poles)
        self.use_control_timestep(control_timestep, default=None)
        self.set_observables(
            {
                # The cart's position, then (cos, sin) of each pole: (n, 1 + 2 * poles).
                "position": Concatenated(
                    [
                        BoundField("qpos", self.cartpole.slider),
                        BoundField("xmat", self.cartpole.poles, (slice(None), _ZZ_XZ), flat=True),
                    ]
                ),
                "velocity": BoundField("qvel", self._joints),
            }
        )

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: swing-up, the cart at N(0, 0.01) and the first pole at
        pi + N(0, 0.01), the others N(0, 0.1); balance, the cart U(-0.1, 0.1) and each
        pole U(-0.034, 0.034); then every velocity N(0, 0.01)."""
        qpos, nv = physics.data.qpos, physics.model.nv
        if self._swing_up:
            qpos[0] = 0.01 * random_state.randn()
            qpos[1] = np.pi + 0.01 * random_state.randn()
            qpos[2:] = 0.1 * random_state.randn(nv - 2)
        else:
            qpos[0] = random_state.uniform(-0.1, 0.1)
            qpos[1:] = random_state.uniform(-0.034, 0.034, nv - 1)
        physics.data.qvel[:] = 0.01 * random_state.randn(nv)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        cosines = physics.bind(self.cartpole.poles).xmat[:, :, 8]
        # The ufuncs' reductions are what ndarray's prod and min compute, without their
        # Python wrappers (a microsecond each, every step).
        if self._sparse:
            cart = physics.bind(self.cartpole.slider).qpos[:, 0]
            cart_in_bounds = _CART_IN_BOUNDS(cart)
            angle_in_bounds = np.multiply.reduce(_ANGLE_IN_BOUNDS(cosines), axis=1)
            return cart_in_bounds * angle_in_bounds
        joints = physics.bind(self._joints)
        values = joints.qvel  # a copy, (n, 1 + poles): the cart's column gets its position
        values[:, 0] = joints.qpos[:, 0]
        gaussians = self._gaussians(values)  # centered's, then each pole's small velocity's
        small_control = (_FOUR + _SMALL_CONTROL(physics.field("ctrl")[:, 0])) / _FIVE
        if self._single_pole:  # a row of one is its own mean and minimum
            centered, small_velocity = ((_ONE + gaussians) / _TWO).T
            upright = (cosines[:, 0] + _ONE) / _TWO
        else:
            centered = (_ONE + gaussians[:, 0]) / _TWO
            small_velocity = (_ONE + np.minimum.reduce(gaussians[:, 1:], axis=1)) / _TWO
            upright = row_means((cosines + _ONE) / _TWO)
        return upright * small_control * small_velocity * centered


_SWING = "Swing up and balance a pole on a cart"
for _name, _kwargs, _description, _tags in (
    ("balance", {"swing_up": False, "sparse": False},
     "Balance a pole on a cart", ("benchmarking",)),
    ("balance_sparse", {"swing_up": False, "sparse": True},
     "Balance a pole on a cart; reward 1 while upright and centred", ("benchmarking",)),
    ("swingup", {"swing_up": True, "sparse": False}, _SWING, ("benchmarking",)),
    ("swingup_sparse", {"swing_up": True, "sparse": True},
     f"{_SWING}; reward 1 while upright and centred", ("benchmarking",)),
    ("two_poles", {"swing_up": True, "sparse": False, "num_poles": 2},
     "Swing up and balance a chain of two poles on a cart", ()),
    ("three_poles", {"swing_up": True, "sparse": False, "num_poles": 3},
     "Swing up and balance a chain of three poles on a cart", ()),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry("cartpole", _name, Balance, _kwargs, TIME_LIMIT, _description, _tags)
    )
