"""Global settings of composed models (`mjcf.compose.global_settings`): an attached model's
`<option>`, `<size>`, `<visual>`, `<statistic>` and `<compiler>` merge into the model it
goes into by dm_control's rules (MuJoCo's documented merging table, where dm_control has
none), every conflict is named in one error, and values written on either model after
the attach are the composed model's, as in dm_control. References: MuJoCo's own
attachment in its "merge" mode, and dm_control's own `mjcf` from its published wheel (its
schema's rules here; the same scenarios read by both: test_global_settings_dm_control.py)."""

from __future__ import annotations

import re
import warnings
import zipfile

import mujoco
import numpy as np
import pytest

import composer
import mjcf
from entities import robots
from mjcf.compose import global_settings
from mjcf.compose.settings import OWN_COMPILER_SETTINGS
from tests import dm_control_wheel
from tests.conftest import UR5E, gym_model

Obj = mujoco.mjtObj


def _compiled(model: mjcf.RootElement) -> mujoco.MjModel:
    return mjcf.Physics.from_mjcf_model(model).model


# -- the base arena with robots that set their own timestep ---------------------------------


def test_the_base_arena_with_a_robot_of_its_own_timestep_compiles_at_the_smaller_step() -> None:
    arena = composer.Arena()  # dm_control's base arena: 2 ms
    ant = robots.from_path(gym_model("ant"), without_floor=True)  # 10 ms, RK4
    arena.add_free_entity(ant)
    assert arena.mjcf_model.option.timestep == 0.002
    assert ant.mjcf_model.option.timestep == 0.002  # shared: the composed model's
    assert arena.mjcf_model.option.integrator == "RK4"  # given by the ant alone
    model = _compiled(arena.mjcf_model)
    assert model.opt.timestep == 0.002
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4
    assert model.opt.noslip_iterations == 5  # the arena's, larger than none

    hopper = robots.from_path(gym_model("hopper"), without_floor=True)
    hopper.mjcf_model.option.timestep = 0.0005  # a robot simulated at a finer step
    arena.attach(hopper)
    assert arena.mjcf_model.option.timestep == 0.0005
    assert _compiled(arena.mjcf_model).opt.timestep == 0.0005


def test_a_task_on_the_base_arena_steps_the_composed_timestep() -> None:
    class Hop(composer.Task):
        def __init__(self) -> None:
            self._arena = composer.Arena()
            self._hopper = robots.from_path(gym_model("hopper"), without_floor=True)
            self._hopper.mjcf_model.option.timestep = 0.001
            self._arena.attach(self._hopper)
            self.set_timesteps(control_timestep=0.01, physics_timestep=0.001)

        @property
        def root_entity(self) -> composer.Entity:
            return self._arena

        def get_reward(self, physics: mjcf.Physics) -> float:
            return 0.0

    task = Hop()
    assert task.physics_timestep == 0.001
    assert task.physics_steps_per_control_step == 10
    environment = composer.Environment(task)
    environment.reset(seed=0)
    assert environment.physics.model.opt.timestep == 0.001
    environment.close()


# -- each merge rule --------------------------------------------------------------------------


def _ruled() -> list[tuple[str, str, str]]:
    """(element path, attribute, rule) of every setting two models may give differently."""
    model = mjcf.RootElement()
    return [
        (path, name, rule)
        for path, element in global_settings.settings_elements(model)
        for name, attribute in element.spec.attributes.items()
        if (rule := global_settings.rule_of(path, attribute)) is not None
    ]


_RULED = _ruled()
_TEXTS = {"real": ("0.004", "0.001"), "int": ("3", "9"), "keyword": ("enable", "disable")}
_TEXT_OF = {"memory": ("2M", "1500K"), "actuatorgroupdisable": ("1 3", "2"), "zfar": ("40", "80")}
_SIZES = ("nkey", "nuserdata", "njmax", "nconmax", "narena", *(f"nuser_{k}" for k in (
    "body", "jnt", "geom", "site", "cam", "tendon", "actuator", "sensor")))  # fmt: skip


def _settings_xml(path: str, name: str, text: str) -> str:
    tags = path.split(".")
    inner = f'<{tags[-1]} {name}="{text}"/>'
    return f"<{tags[0]}>{inner}</{tags[0]}>" if len(tags) > 1 else inner


def _compiled_settings(model: mujoco.MjModel) -> dict[str, np.ndarray]:
    found = {f"size.{name}": np.array(getattr(model, name)) for name in _SIZES}
    for prefix, struct in (
        ("opt", model.opt),
        ("map", model.vis.map),
        ("global", model.vis.global_),
    ):
        for name in dir(struct):
            value = getattr(struct, name)
            if not name.startswith("_") and isinstance(value, int | float | np.ndarray):
                found[f"{prefix}.{name}"] = np.array(value)
    return found


@pytest.mark.parametrize(("path", "name", "rule"), _RULED, ids=[f"{p}.{n}" for p, n, _ in _RULED])
def test_each_rule_merges_as_mujoco_s_own_attach_merges(path: str, name: str, rule: str) -> None:
    """Both orders of two values, merged by us and by MuJoCo's own attachment under
    `<compiler conflict="merge">` (its documented merging table), compile alike; the
    attached model reads the composed value too."""
    spec = global_settings.settings_elements(mjcf.RootElement())
    attribute = dict(spec)[path].spec.attributes[name]
    texts = _TEXT_OF[name] if name in _TEXT_OF else _TEXTS[attribute.kind]
    body = '<worldbody><body name="b"><joint/><geom size=".1"/></body></worldbody>'
    for mine, theirs in (texts, texts[::-1]):
        parent_xml = f"<mujoco>{_settings_xml(path, name, mine)}<worldbody/></mujoco>"
        child_xml = f"<mujoco>{_settings_xml(path, name, theirs)}{body}</mujoco>"
        parent, child = mjcf.from_xml_string(parent_xml), mjcf.from_xml_string(child_xml)
        parent.attach(child)
        assert np.array_equal(
            np.atleast_1d(getattr(_element(child, path), name)),
            np.atleast_1d(getattr(_element(parent, path), name)),
        )
        if name == "nstack":  # undocumented: MuJoCo keeps the parent's, we take the larger
            assert parent.size.nstack == 9
            continue
        reference = mujoco.MjSpec.from_string(
            parent_xml.replace("<mujoco>", '<mujoco><compiler conflict="merge"/>').replace(
                "<worldbody/>", '<worldbody><frame name="f"/></worldbody>'
            )
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # MuJoCo reports each merge
            reference.attach(
                mujoco.MjSpec.from_string(child_xml), frame=reference.frame("f"), prefix="c/"
            )
            try:
                theirs_model = reference.compile()
            except ValueError as error:  # a flag that needs more (ipc: the discrete integrator)
                with pytest.raises(mjcf.CompileError, match=re.escape(str(error))):
                    _compiled(parent)
                continue
        ours, expected = _compiled_settings(_compiled(parent)), _compiled_settings(theirs_model)
        differing = [key for key in expected if not np.array_equal(ours[key], expected[key])]
        assert differing == [], (mine, theirs)


def _element(model: mjcf.RootElement, path: str) -> mjcf.Element:
    element = model
    for tag in path.split("."):
        element = getattr(element, tag)
    return element


def test_the_rules_mujoco_leaves_undocumented_name_attributes_it_has() -> None:
    elements = dict(global_settings.settings_elements(mjcf.RootElement()))
    for path, name in global_settings.UNDOCUMENTED_RULES:
        assert elements[path].spec.attributes[name].merge is None


def test_a_flag_either_model_turns_from_its_default_is_the_composed_models() -> None:
    """MuJoCo's documented merge ORs the flags (dm_control refuses two values)."""
    arena = composer.Arena().mjcf_model
    arena.option.flag.gravity = "enable"
    hopper = mjcf.from_path(gym_model("hopper"))
    hopper.option.flag.gravity = "disable"
    hopper.option.flag.energy = "enable"
    arena.attach(hopper)
    assert (arena.option.flag.gravity, arena.option.flag.energy) == ("disable", "enable")
    model = _compiled(arena)
    assert model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY
    assert model.opt.enableflags & mujoco.mjtEnableBit.mjENBL_ENERGY


def test_memory_merges_to_the_larger_in_bytes_written_as_dm_control_writes_it() -> None:
    cases = [("10000", "1M", "1048576"), ("2M", "1500K", "2097152"), (None, "1500K", "1500K")]
    for mine, theirs, expected in cases:
        parent, child = mjcf.RootElement(model="p"), mjcf.RootElement(model="c")
        parent.size.memory = mine
        child.size.memory = theirs
        parent.attach(child)
        assert parent.size.memory == expected
        assert f'memory="{expected}"' in parent.to_xml_string()
        alone = mujoco.MjModel.from_xml_string(f'<mujoco><size memory="{expected}"/></mujoco>')
        assert _compiled(parent).narena == alone.narena


def test_memory_with_an_njmax_of_another_model_is_refused_at_attach() -> None:
    parent, child = mjcf.RootElement(model="p"), mjcf.RootElement(model="c")
    parent.size.memory = "1M"
    child.size.njmax = 100  # MuJoCo reads one of the two
    message = r"<size>: memory \(model 'p'\), njmax \(model 'c'\): at most one of"
    with pytest.raises(mjcf.AttachmentError, match=message):
        parent.attach(child)
    assert child.parent_model is None and parent.size.njmax is None


def test_file_folders_stay_each_models_own(menagerie) -> None:
    """dm_control keeps the parent's meshdir ("replace"); here each model keeps its own, as
    its files are found from it, and the composed model compiles with the arm's meshes."""
    scene = mjcf.RootElement(model="scene")
    scene.compiler.meshdir = "no_such_folder"
    arm = mjcf.from_path(UR5E)  # meshdir="assets"
    scene.attach(arm)
    assert scene.compiler.meshdir == "no_such_folder" and arm.compiler.meshdir == "assets"
    alone = mjcf.Physics.from_mjcf_model(mjcf.from_path(UR5E)).model
    composed = _compiled(scene)
    assert composed.nmesh == alone.nmesh and np.array_equal(composed.mesh_vert, alone.mesh_vert)


# -- conflicts --------------------------------------------------------------------------------


def test_every_conflict_is_named_in_one_error_and_nothing_changes() -> None:
    """gymnasium's pusher and reacher disagree on integrator and gravity, and the arena
    and the reacher, edited, on a headlight and a bound: one error names all four."""
    arena = composer.Arena().mjcf_model
    pusher = mjcf.from_path(gym_model("pusher"))  # Euler, no gravity
    arena.attach(pusher)
    reacher = mjcf.from_path(gym_model("reacher"))  # RK4, gravity 0 0 -9.81
    reacher.visual.headlight.ambient = [0.5, 0.5, 0.5]
    reacher.compiler.boundmass = 0.01
    before, reacher_before = arena.to_xml_string(), reacher.to_xml_string()
    with pytest.raises(mjcf.AttachmentError) as caught:
        arena.attach(reacher)
    message = str(caught.value)
    assert message.startswith(
        "Conflicting values for attributes `boundmass`, `gravity`, `integrator`, `ambient`"
    )
    for line in (
        "<compiler> boundmass: '1e-05' in model 'arena', '0.01' in model 'reacher'",
        "<option> gravity: '0 0 0' in model 'arena', '0 0 -9.81' in model 'reacher'",
        "<option> integrator: 'Euler' in model 'arena', 'RK4' in model 'reacher'",
        "<visual>/<headlight> ambient: '0.3 0.3 0.3' in model 'arena', '0.5 0.5 0.5' in model",
    ):
        assert line in message
    assert isinstance(caught.value, ValueError)  # what dm_control raises
    assert arena.to_xml_string() == before and reacher.to_xml_string() == reacher_before
    assert reacher.parent_model is None and reacher.option.timestep == 0.01


def test_a_sibling_conflict_is_found_at_attach() -> None:
    """The second robot is checked against what the first one merged into the arena."""
    arena = mjcf.RootElement(model="arena")
    arena.attach(mjcf.from_path(gym_model("pusher")))  # Euler
    with pytest.raises(mjcf.AttachmentError, match="<option> integrator: 'Euler' in model"):
        arena.attach(mjcf.from_path(gym_model("swimmer")))  # RK4


def test_a_conflict_deep_in_a_composed_tree_names_the_outermost_model() -> None:
    arena, base, arm = (mjcf.RootElement(model=name) for name in ("arena", "base", "arm"))
    arena.option.integrator = "RK4"
    mount = base.worldbody.add("site", name="mount")
    arena.attach(base)
    arm.option.integrator = "implicitfast"
    with pytest.raises(mjcf.AttachmentError, match=r"'RK4' in model 'arena', 'implicitfast'"):
        mount.attach(arm)


# -- values written after the attach -----------------------------------------------------------


def test_a_bound_written_on_the_walker_after_the_attach_is_the_composed_models() -> None:
    """A project sets `compiler.boundmass = 0` on its walker once attached: dm_control then
    compiles every body unbounded, the arena's too."""
    arena = composer.Arena()  # boundmass 1e-5
    walker = mjcf.RootElement(model="walker")
    body = walker.worldbody.add("body", name="feather")
    body.add("inertial", pos=[0, 0, 0], mass=1e-7, diaginertia=[1e-9] * 3)
    body.add("joint", type="slide")
    arena.mjcf_model.attach(walker)
    assert _compiled(arena.mjcf_model).body_mass[-1] == pytest.approx(1e-5)  # bounded
    walker.compiler.boundmass = 0
    assert arena.mjcf_model.compiler.boundmass == 0
    assert _compiled(arena.mjcf_model).body_mass[-1] == pytest.approx(1e-7)
    walker.compiler.boundinertia = 0
    assert 'boundinertia="0"' in arena.mjcf_model.to_xml_string()


def test_visual_settings_rewritten_every_episode_are_compiled_each_episode() -> None:
    """A task rewrites its walker's `<visual>` in `initialize_episode_mjcf`, after the
    walker was attached to an arena whose headlight it then replaces."""

    class Lit(composer.Task):
        def __init__(self) -> None:
            self._arena = composer.Arena()
            self._hopper = robots.from_path(gym_model("hopper"), without_floor=True)
            self._arena.attach(self._hopper)
            self.brightness: list[float] = []

        @property
        def root_entity(self) -> composer.Entity:
            return self._arena

        def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
            level = float(random_state.uniform(0.1, 0.9))
            self.brightness.append(level)
            self._hopper.mjcf_model.visual.headlight.ambient = [level] * 3
            self._hopper.mjcf_model.visual.map.znear = level / 100

        def get_reward(self, physics: mjcf.Physics) -> float:
            return 0.0

    task = Lit()
    environment = composer.Environment(task)
    for seed in range(3):
        environment.reset(seed=seed)
        vis = environment.physics.model.vis
        assert np.allclose(vis.headlight.ambient, [task.brightness[-1]] * 3)
        assert vis.map.znear == pytest.approx(task.brightness[-1] / 100)
        assert task.root_entity.mjcf_model.visual.headlight.ambient[0] == task.brightness[-1]
    assert len(set(task.brightness)) == 3
    environment.close()


def test_a_write_after_the_attach_replaces_what_the_merge_gave() -> None:
    arena, robot = mjcf.RootElement(model="arena"), mjcf.RootElement(model="robot")
    arena.option.timestep = 0.002
    robot.option.timestep = 0.005
    arena.attach(robot)
    arena.option.timestep = 0.01  # a task's physics_timestep: larger than the robot's own
    assert robot.option.timestep == 0.01 and _compiled(arena).opt.timestep == 0.01
    robot.option.timestep = 0.004  # from either model
    assert arena.option.timestep == 0.004 and _compiled(arena).opt.timestep == 0.004
    robot.option.flag.gravity = "disable"
    assert arena.option.flag.gravity == "disable"
    del arena.option.flag.gravity
    assert robot.option.flag.gravity is None


def test_an_attached_model_written_or_compiled_alone_has_the_shared_settings() -> None:
    arena, robot = mjcf.RootElement(model="arena"), mjcf.RootElement(model="robot")
    robot.worldbody.add("geom", size=[0.1])
    arena.attach(robot)
    assert "timestep" not in robot.to_xml_string()
    assert _compiled(robot).opt.timestep == 0.002
    arena.option.timestep = 0.003  # a change of the arena only
    assert 'timestep="0.003"' in robot.to_xml_string()
    assert _compiled(robot).opt.timestep == 0.003
    assert robot.option.to_xml_string(pretty_print=False) == '<option timestep="0.003"/>'


def test_models_attached_inside_an_attached_model_share_the_outermost_models() -> None:
    """dm_control loses a write to a model attached before its parent was attached (it
    goes to the parent's storage of before); here it is the composed model's too."""
    arena, base, arm = (mjcf.RootElement(model=name) for name in ("arena", "base", "arm"))
    arm.option.timestep = 0.001
    base.worldbody.add("site", name="mount").attach(arm)
    arena.attach(base)
    assert arena.option.timestep == 0.001
    arm.option.timestep = 0.0005
    assert arena.option.timestep == base.option.timestep == 0.0005
    assert _compiled(arena).opt.timestep == 0.0005


# -- detach, copies, removal --------------------------------------------------------------------


def test_a_detached_model_keeps_a_copy_and_the_parent_keeps_the_merged_values() -> None:
    arena, robot = mjcf.RootElement(model="arena"), mjcf.RootElement(model="robot")
    arena.option.timestep = 0.002
    robot.option.set_attributes(timestep=0.001, integrator="RK4")
    robot.compiler.angle = "radian"
    arena.attach(robot)
    robot.detach()
    assert (arena.option.timestep, arena.option.integrator) == (0.001, "RK4")
    robot.option.timestep = 0.01  # its own again
    assert arena.option.timestep == 0.001 and robot.compiler.angle == "radian"
    assert arena.compiler.angle is None


def test_copies_of_a_composed_model_share_their_own_settings() -> None:
    import copy

    arena, robot = mjcf.RootElement(model="arena"), mjcf.RootElement(model="robot")
    robot.worldbody.add("geom", size=[0.1])
    arena.attach(robot)
    twin = copy.deepcopy(arena)
    twin_robot = twin.find("attachment_frame", "robot").attached_model
    twin_robot.option.timestep = 0.004
    assert twin.option.timestep == 0.004 and arena.option.timestep is None
    robot_copy = copy.deepcopy(robot)  # a copy of an attached model: detached, its own
    robot_copy.option.timestep = 0.007
    assert arena.option.timestep is None and robot_copy.option.timestep == 0.007


def test_emptying_a_shared_settings_element_empties_it_for_every_model() -> None:
    arena, robot = mjcf.RootElement(model="arena"), mjcf.RootElement(model="robot")
    robot.visual.headlight.ambient = [0.2, 0.2, 0.2]
    arena.attach(robot)
    with pytest.raises(mjcf.AttachmentError, match="affect_attachments"):
        arena.visual.headlight.remove()
    robot.visual.headlight.remove()  # as dm_control: the shared values go
    assert arena.visual.headlight.ambient is None
    robot.visual.headlight.ambient = [0.4, 0.4, 0.4]
    assert np.allclose(_compiled(arena).vis.headlight.ambient, 0.4)


def test_the_rules_are_dm_control_s_wherever_dm_control_has_one() -> None:
    """Every attribute dm_control's schema lets two models set differently merges with
    dm_control's rule here (MuJoCo's documented table agrees), or is one each model keeps
    for itself (`model`, and the compiler's file folders, where dm_control keeps the
    parent's); the rules dm_control lacks are MuJoCo's documented ones, and `nstack`."""
    from lxml import etree

    with zipfile.ZipFile(dm_control_wheel.wheel()) as archive:
        schema = etree.fromstring(archive.read("dm_control/mjcf/schema.xml"))
    theirs: dict[tuple[str, str], str] = {}
    for attribute in schema.iter("attribute"):
        if attribute.get("conflict_allowed") == "true":
            path = ".".join([e.get("name") for e in attribute.iterancestors("element")][::-1][1:])
            theirs[(path, attribute.get("name"))] = attribute.get("conflict_behavior", "replace")
    assert len(theirs) == 20  # those the issue lists: none missing from it
    ours = {(path, name): rule for path, name, rule in _RULED}
    kept = {("", "model")} | {("compiler", name) for name in OWN_COMPILER_SETTINGS}
    for key, rule in theirs.items():
        expected = {"max_bytes": "max"}.get(rule, rule)
        assert (key in kept) if rule == "replace" else ours.get(key) == expected, key
    elements = dict(global_settings.settings_elements(mjcf.RootElement()))
    for path, name in set(ours) - set(theirs):
        assert elements[path].spec.attributes[name].merge or name == "nstack", (path, name)
