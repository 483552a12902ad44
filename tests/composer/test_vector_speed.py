"""What a VectorEnvironment chooses for speed, and that it changes no number: its physics
threads by the work of a step call (`composer.vector.threads`), MuJoCo's profiling timer
left out of its batch's calls (`composer.batch.timer`), and one model for every simulation
while the models are equal but for their textures (`composer.vector.models`)."""

from __future__ import annotations

import copy
import os

import mujoco
import numpy as np
import pytest
from gymnasium.vector import SyncVectorEnv

import composer
from composer.batch import timer
from composer.vector import VectorEnvironment, threads
from composer.vector.models import SameModels
from tests.composer.vector_scenes import BatchedSwing
from tests.vector_runs import assert_same_runs

_HINGE = """<mujoco><worldbody><body><joint type="hinge"/><geom size=".1" mass="1"/>
</body></worldbody></mujoco>"""


def test_a_step_of_a_model_is_timed_on_a_scratch_copy():
    model = mujoco.MjModel.from_xml_string(_HINGE)
    assert threads.step_seconds(model) > 0


_W = threads.WORK_PER_THREAD


@pytest.mark.parametrize(
    ("step", "num_envs", "substeps", "cpus", "expected"),
    [
        (_W / 10, 8, 1, 4, 1),  # 0.8 of the work a thread: one thread
        (_W / 10, 16, 1, 4, 1),  # 1.6: still one (a thread for each WORK_PER_THREAD)
        (_W / 10, 32, 1, 4, 3),  # 3.2: three
        (_W / 10, 20, 5, 4, 4),  # 10: the CPUs
        (_W / 10, 2, 1000, 4, 2),  # 200, but two simulations
        (_W / 10, 1000, 1, 1, 1),  # one CPU
        (_W * 100, 1, 5, 4, 1),  # one simulation
    ],
)
def test_a_thread_for_each_work_per_thread_of_physics_in_a_call(
    monkeypatch, step, num_envs, substeps, cpus, expected
):
    monkeypatch.setattr(threads, "step_seconds", lambda model: step)
    model = mujoco.MjModel.from_xml_string(_HINGE)
    assert threads.physics_threads(model, num_envs, substeps, cpus) == expected


def test_the_default_follows_the_rule_and_a_given_count_is_kept(monkeypatch):
    monkeypatch.setattr(threads, "step_seconds", lambda model: 1.0)  # a second a step
    assert VectorEnvironment(BatchedSwing, 2).nthread == min(2, _usable_cpus())
    monkeypatch.setattr(threads, "step_seconds", lambda model: 1e-9)
    assert VectorEnvironment(BatchedSwing, 2).nthread == 1
    assert VectorEnvironment(BatchedSwing, 2, nthread=2).nthread == 2


def _usable_cpus() -> int:
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


@pytest.mark.parametrize("nthread", [1, 2])
def test_any_thread_count_gives_the_single_environments_trajectories(nthread):
    def factory() -> BatchedSwing:
        return BatchedSwing(terminate_above=1.0)

    vector = VectorEnvironment(factory, 3, nthread=nthread, time_limit=0.5)
    reference = SyncVectorEnv(
        [lambda: composer.Environment(factory(), time_limit=0.5) for _ in range(3)]
    )
    assert assert_same_runs(vector, reference, steps=60, seed=3) > 0  # through autoresets


def test_the_batch_steps_without_mujocos_timer_and_puts_it_back():
    vector = VectorEnvironment(BatchedSwing, 2)
    vector.reset(seed=0)
    vector.step(np.zeros((2, 1)))
    model = mujoco.MjModel.from_xml_string(_HINGE)
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data)  # the bindings' timer, installed again after the step
    assert data.timer[mujoco.mjtTimer.mjTIMER_STEP].duration > 0


def test_a_timer_callback_other_than_the_bindings_is_left_as_it_is():
    callback = timer._MJCB_TIME
    if callback is None:
        pytest.skip("MuJoCo's library was not found: the bindings' timer stays installed")
    vector = VectorEnvironment(BatchedSwing, 2)
    vector.reset(seed=0)
    installed = callback.value
    callback.value = None  # MuJoCo's own default, as a C program has it
    try:
        vector.step(np.zeros((2, 1)))
        assert callback.value is None
    finally:
        callback.value = installed


_TEXTURED = """<mujoco><asset><texture name="grid" type="2d" builtin="checker" width="64"
height="64"/><material name="grid" texture="grid"/></asset><worldbody><body><joint
type="hinge"/><geom size=".1" mass="1" material="grid"/></body></worldbody></mujoco>"""


def test_models_share_one_while_equal_but_their_textures():
    first = mujoco.MjModel.from_xml_string(_TEXTURED)
    other = copy.copy(first)
    same = SameModels(2)
    same.update([first, other], [0, 1])
    assert same.identical
    other.tex_data[:16] = 255 - other.tex_data[:16]  # only rendering reads textures
    same.update([first, other], [1])
    assert same.identical
    for edit, undo in [
        (lambda m: m.body_mass.__setitem__(1, 2.0), lambda m: m.body_mass.__setitem__(1, 1.0)),
        (
            lambda m: m.opt.gravity.__setitem__(2, -1.0),
            lambda m: m.opt.gravity.__setitem__(2, -9.81),
        ),
        (lambda m: setattr(m.opt, "timestep", 0.001), lambda m: setattr(m.opt, "timestep", 0.002)),
    ]:
        edit(other)
        same.update([first, other], [1])
        assert not same.identical
        undo(other)
        same.update([first, other], [1])
        assert same.identical
