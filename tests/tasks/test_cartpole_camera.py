"""CartpoleSwingup renders through a camera that follows the cart: wherever the cart is on
its rail, the cart is in the middle of the frame and the whole pole is in it."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from tests.tasks.helpers import make


@pytest.mark.parametrize("angle", [0.0, np.pi], ids=["upright", "hanging"])
def test_the_cart_stays_in_the_middle_of_the_frame_and_the_pole_in_it(angle):
    env = make("composer/CartpoleSwingup-v0", render_mode="rgb_array")
    env.reset(seed=0)
    task, physics = env.unwrapped.task, env.unwrapped.physics
    assert task.render_camera == "cartpole/track"
    cart, pole = (mujoco.mj_name2id(physics.model, mujoco.mjtObj.mjOBJ_GEOM, f"cartpole/{name}")
                  for name in ("cart", "pole"))  # fmt: skip
    for position in (-1.9, 0.0, 1.9):  # the rail's ends are at +-2 m
        physics.bind(task.cartpole.slider).qpos = position
        physics.bind(task.cartpole.hinge).qpos = angle
        objects = physics.render(240, 320, camera_id=task.render_camera, segmentation=True)
        _, columns = np.nonzero(objects[..., 0] == cart)
        assert abs(columns.mean() - 160) < 8, position  # centred, wherever the cart is
        pole_rows, _ = np.nonzero(objects[..., 0] == pole)
        # The pole, a metre long, is seen whole: well inside the frame at both ends.
        assert pole_rows.min() > 5 and pole_rows.max() < 235, (position, angle)
        assert np.ptp(pole_rows) > 60
    env.close()
