"""reset_context forwards once, when the block ends: what the block reads through bindings
and named access, and the simulation after it, must be what resetting and forwarding at
once (two forwards, dm_control's way) gives, bit for bit."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from mjcf import Physics, errors
from tests.conftest import gym_model

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
_DERIVED = ("xpos", "xquat", "qacc", "qfrc_constraint", "sensordata", "actuator_force", "cacc")


def _snapshot(physics: Physics) -> dict[str, bytes]:
    model, data = physics.model, physics.data
    state = np.empty(mujoco.mj_stateSize(model, _STATE))
    mujoco.mj_getState(model, data, state, _STATE)
    found = {"state": state.tobytes(), "ncon": bytes([data.ncon % 256])}
    found.update({name: getattr(data, name).tobytes() for name in _DERIVED})
    found["warnings"] = data.warning.number.tobytes()
    return found


def _hook(physics: Physics, rng: np.random.Generator, log: list) -> None:
    """What an episode's initialization does: read derived fields, write the state, read
    them again."""
    torso = physics.bind_names(mujoco.mjtObj.mjOBJ_BODY, "torso")
    log.append(torso.xpos.copy())  # the reset state's, computed now
    log.append(physics.named.data.cacc["torso"].copy())  # computed only on demand
    joints = physics.bind_names(mujoco.mjtObj.mjOBJ_JOINT, ["hip_1", "ankle_1", "root"])
    joints.qpos = joints.qpos + rng.uniform(-0.2, 0.2, joints.qpos.shape)
    log.append(torso.xpos.copy())  # after the write
    log.append(physics.bind_names(mujoco.mjtObj.mjOBJ_BODY, "torso").xmat.copy())


@pytest.mark.parametrize("keyframe", [None, 0])
def test_one_forward_gives_what_reset_then_forward_gives(keyframe):
    xml = gym_model("ant").read_text()
    if keyframe is not None:
        xml = xml.replace("</mujoco>", '<keyframe><key qpos="0 0 0.9 1 0 0 0 0 1 0 -1 0 -1 0 1"/>'
                          "</keyframe></mujoco>")  # fmt: skip
    lazy, eager = Physics.from_xml_string(xml), Physics.from_xml_string(xml)
    for physics in (lazy, eager):
        physics.data.ctrl[:] = 0.3
        physics.step(7)  # a state to reset from
    for episode in range(3):
        read_lazy: list = []
        read_eager: list = []
        with lazy.reset_context(keyframe):
            _hook(lazy, np.random.default_rng(episode), read_lazy)
        eager.reset(keyframe)  # forwards at once, and again after the hook
        _hook(eager, np.random.default_rng(episode), read_eager)
        eager.forward()
        eager.check_invalid_state()
        assert [a.tobytes() for a in read_lazy] == [b.tobytes() for b in read_eager]
        assert _snapshot(lazy) == _snapshot(eager)
        assert not lazy.is_dirty
        for physics in (lazy, eager):
            physics.data.ctrl[:] = -0.2
            physics.step(5)
        assert _snapshot(lazy) == _snapshot(eager)


def test_a_block_that_reads_nothing_leaves_the_reset_state_forwarded():
    physics = Physics.from_xml_path(gym_model("ant"))
    physics.step(20)
    with physics.reset_context():
        assert not physics.is_dirty
    fresh = Physics.from_xml_path(gym_model("ant"))
    fresh.forward()
    assert _snapshot(physics) == _snapshot(fresh)


def test_an_error_in_the_block_propagates_without_the_check_and_a_bad_state_raises():
    physics = Physics.from_xml_path(gym_model("ant"))
    with pytest.raises(KeyError, match="mine"), physics.reset_context():
        physics.named.data.qvel["root"] = np.nan  # never checked: the block raises first
        raise KeyError("mine")
    with pytest.raises(errors.PhysicsError, match="qacc is not finite"), physics.reset_context():
        physics.named.data.qvel["root"] = np.nan
    with pytest.raises(errors.NotFoundError), physics.reset_context("no such keyframe"):
        pass
