"""The divergence check after a step takes MuJoCo's word for qacc where MuJoCo checked it:
its verdict must be the full check's, whatever the integrator, flags and history."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from mjcf import Physics, errors
from mjcf.sim import validity

# A pendulum with a strong motor and a free box falling onto the floor: contacts, a
# constraint solver, and accelerations a large control makes non-finite. The whip's
# damping is absurd: a kick leaves its acceleration finite at the step's start, and RK4's
# later stages, which move it, make theirs infinite.
MODEL = """
<mujoco>
  <option integrator="{integrator}">
    <flag {flags}/>
  </option>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <body name="arm" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0" damping="{damping}"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
    </body>
    <body name="whip" pos="0 0.5 1">
      <joint name="whip" type="hinge" axis="0 1 0" damping="1e305"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03"/>
    </body>
    <body name="box" pos="0.5 0 0.3">
      <freejoint name="free"/>
      <geom type="box" size="0.05 0.05 0.05"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="motor" joint="hinge" gear="1e150"/>
    <motor name="kick" joint="whip"/>
  </actuator>
</mujoco>
"""
INTEGRATORS = ("Euler", "implicit", "implicitfast", "RK4")
FLAGS = ("", 'fwdinv="enable"', 'autoreset="disable"')


def _full_verdict(physics: Physics) -> str | None:
    """What the check says looking at qacc whatever the step did."""
    try:
        validity.raise_if_invalid(physics.model, physics.data, physics.data.warning.number)
    except errors.PhysicsError as e:
        return str(e)
    return None


def _verdict(physics: Physics) -> str | None:
    try:
        physics.check_invalid_state()
    except errors.PhysicsError as e:
        return str(e)
    return None


@pytest.mark.parametrize("legacy", [True, False])
@pytest.mark.parametrize("flags", FLAGS)
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_the_check_after_a_step_says_what_the_full_check_says(integrator, flags, legacy):
    damping = "0" if integrator == "RK4" else "0.5"  # Euler integrates damping implicitly
    xml = MODEL.format(integrator=integrator, flags=flags, damping=damping)
    physics = Physics.from_xml_string(xml)
    physics.legacy_step = legacy
    motor = physics.bind_names(mujoco.mjtObj.mjOBJ_ACTUATOR, "motor")
    kick = physics.bind_names(mujoco.mjtObj.mjOBJ_ACTUATOR, "kick")
    free = physics.bind_names(mujoco.mjtObj.mjOBJ_JOINT, "free")
    rng = np.random.default_rng(0)
    seen = set()
    for _ in range(300):
        events = ["step", "step", "step", "huge control", "kick", "nan velocity", "read qacc"]
        event = rng.choice(events)
        kick.ctrl = 0.0
        if event == "kick":
            kick.ctrl = 1e6
            physics.step()
        elif event == "huge control":
            motor.ctrl = 1e160  # the force overflows: qacc is not finite
        elif event == "nan velocity":
            free.qvel = [np.nan, 0, 0, 0, 0, 0]  # written, not stepped: seen in qacc
        elif event == "read qacc":
            _ = free.qacc  # forwards: qacc recomputed where no MuJoCo check sees it
        else:
            motor.ctrl = rng.uniform(-1e-150, 1e-150)
            physics.step(int(rng.integers(1, 4)))
        verdict, full = _verdict(physics), _full_verdict(physics)
        assert verdict == full, f"after {event}"
        seen.add((event, full is None))
        if full is not None:
            physics.reset()
    assert ("step", True) in seen and ("read qacc", False) in seen
