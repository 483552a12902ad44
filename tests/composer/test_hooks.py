"""Hooks run in the documented order, only on objects that override them, and a model
change in initialize_episode_mjcf (and only that) recompiles."""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from composer import hooks

STEP_HOOKS = ("before_step", "before_substep", "after_substep", "after_step")


class Recording(composer.Entity):
    """A hinged rod that records every hook call into a shared list."""

    def _build(self, name: str, calls: list) -> None:
        self.calls = calls
        root = self._mjcf_root = mjcf.RootElement(model=name)
        body = root.worldbody.add("body", name="rod", pos=[0, 0, 1])
        self.hinge = body.add("joint", name="hinge", axis=[0, 1, 0])
        self.geom = body.add("geom", type="capsule", fromto=[0, 0, 0, 0, 0, -0.3], size=[0.02])
        root.actuator.add("motor", joint=self.hinge, ctrlrange=[-1, 1])

    def _record(self, hook: str) -> None:
        self.calls.append((self.name, hook))

    def initialize_episode_mjcf(self, random_state):
        self._record("initialize_episode_mjcf")

    def after_compile(self, physics, random_state):
        self._record("after_compile")

    def initialize_episode(self, physics, random_state):
        self._record("initialize_episode")

    def before_step(self, physics, random_state):
        self._record("before_step")

    def before_substep(self, physics, random_state):
        self._record("before_substep")

    def after_substep(self, physics, random_state):
        self._record("after_substep")

    def after_step(self, physics, random_state):
        self._record("after_step")


class Quiet(composer.Entity):
    """Overrides no hook."""

    def _build(self) -> None:
        self._mjcf_root = mjcf.RootElement(model="quiet")
        self._mjcf_root.worldbody.add("geom", type="sphere", size=[0.1], pos=[1, 1, 0.1])


class RecordingTask(composer.Task):
    """root <- (child <- grandchild), root <- quiet; records its own hooks as 'task'."""

    def __init__(self, calls: list, recolor_on_episode: int | None = None) -> None:
        self.calls = calls
        self.root = Recording("root", calls)
        self.child = Recording("child", calls)
        self.grandchild = Recording("grandchild", calls)
        self.root.attach(self.child)
        self.child.attach(self.grandchild)
        self.root.attach(Quiet())
        self.set_timesteps(control_timestep=0.004, physics_timestep=0.002)
        self.episodes = 0
        self.recolor_on_episode = recolor_on_episode

    @property
    def root_entity(self):
        return self.root

    def get_reward(self, physics):
        return 0.0

    def _record(self, hook: str) -> None:
        self.calls.append(("task", hook))

    def initialize_episode_mjcf(self, random_state):
        self._record("initialize_episode_mjcf")
        self.episodes += 1
        if self.episodes == self.recolor_on_episode:
            self.grandchild.geom.rgba = [1, 0, 0, 1]

    def after_compile(self, physics, random_state):
        self._record("after_compile")

    def initialize_episode(self, physics, random_state):
        self._record("initialize_episode")

    def before_step(self, physics, action, random_state):
        self._record("before_step")
        super().before_step(physics, action, random_state)

    def before_substep(self, physics, action, random_state):
        self._record("before_substep")

    def after_substep(self, physics, random_state):
        self._record("after_substep")

    def after_step(self, physics, random_state):
        self._record("after_step")


EVERYONE = ("task", "root", "child", "grandchild")


def each(hook: str) -> list[tuple[str, str]]:
    return [(who, hook) for who in EVERYONE]


def test_hooks_run_in_the_documented_order_on_task_then_entities_depth_first():
    calls: list = []
    env = composer.Environment(RecordingTask(calls))
    assert calls == each("after_compile")
    calls.clear()
    env.reset(seed=0)
    assert calls == each("initialize_episode_mjcf") + each("initialize_episode")
    calls.clear()
    env.step(np.zeros(3))
    substep = each("before_substep") + each("after_substep")
    assert calls == each("before_step") + substep + substep + each("after_step")


def test_the_documented_hook_names_are_the_order_hooks_first_run_in():
    calls: list = []
    env = composer.Environment(RecordingTask(calls, recolor_on_episode=1))
    calls.clear()
    env.reset(seed=0)  # recompiles: every episode hook runs
    env.step(np.zeros(3))
    first_seen = list(dict.fromkeys(hook for _, hook in calls))
    assert tuple(first_seen) == composer.HOOK_NAMES


def test_only_overridden_hooks_are_dispatched():
    calls: list = []
    task = RecordingTask(calls)
    resolved = hooks.Hooks(task)
    quiet = [e for e in task.root_entity.iter_entities() if isinstance(e, Quiet)]
    assert len(quiet) == 1
    for name in ("after_compile", "initialize_episode", "before_step", "after_step"):
        owners = [method.__self__ for method in getattr(resolved, name)]
        assert quiet[0] not in owners
    assert resolved.has_substep_hooks

    class Plain(composer.NullTask):
        pass

    plain = hooks.Hooks(Plain(Quiet()))
    assert not plain.has_substep_hooks
    assert plain.before_step == () and plain.after_step == () and plain.after_compile == ()


def test_a_model_change_in_initialize_episode_mjcf_recompiles_before_initialize_episode():
    calls: list = []
    task = RecordingTask(calls, recolor_on_episode=2)
    env = composer.Environment(task)
    physics = env.physics
    env.reset(seed=0)
    model = physics.model
    calls.clear()
    env.reset(seed=0)  # episode 2 recolors: recompiled in place
    assert calls == (
        each("initialize_episode_mjcf") + each("after_compile") + each("initialize_episode")
    )
    assert env.physics is physics and physics.model is not model
    geom = physics.bind(task.grandchild.geom)
    np.testing.assert_array_equal(geom.rgba, [1, 0, 0, 1])
    model = physics.model
    calls.clear()
    env.reset(seed=0)  # no change: no recompile
    assert ("task", "after_compile") not in calls
    assert physics.model is model


def test_an_entity_attached_between_resets_has_its_episode_hooks_run_from_the_next_reset():
    # A reset on the model as compiled runs the hooks resolved at the compile; one after an
    # attach finds the new entity's, as walking the tree at every reset would.
    calls: list = []
    task = RecordingTask(calls)
    env = composer.Environment(task, recompile_mjcf_every_episode=None)
    env.reset(seed=0)
    calls.clear()
    env.reset(seed=0)
    assert calls == each("initialize_episode_mjcf") + each("initialize_episode")

    class Late(Quiet):  # no actuator: the action space stays
        def initialize_episode_mjcf(self, random_state):
            calls.append(("late", "initialize_episode_mjcf"))

        def after_compile(self, physics, random_state):
            calls.append(("late", "after_compile"))

        def initialize_episode(self, physics, random_state):
            calls.append(("late", "initialize_episode"))

    task.grandchild.attach(Late())
    calls.clear()
    env.reset(seed=0)
    everyone = (*EVERYONE, "late")
    assert calls == (
        [(who, "initialize_episode_mjcf") for who in everyone]
        + [(who, "after_compile") for who in everyone]
        + [(who, "initialize_episode") for who in everyone]
    )
    calls.clear()
    env.reset(seed=0)
    assert calls == [(who, hook) for hook in ("initialize_episode_mjcf", "initialize_episode")
                     for who in everyone]  # fmt: skip
    env.add_extra_hook("initialize_episode_mjcf", lambda random_state: calls.append("extra"))
    calls.clear()
    env.reset(seed=0)
    assert calls[len(everyone)] == "extra"
