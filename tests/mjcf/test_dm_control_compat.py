"""What dm_control PyMJCF code relies on, beyond building and attaching: copies,
structural equality, scopes, generated names, same-named attachments, size merging and
the errors dm_control code catches."""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import GYM_ASSETS, ROBOTIQ, UR5E


def _leg() -> mjcf.RootElement:
    """dm_control's tutorial leg: an unnamed model of unnamed elements."""
    model = mjcf.RootElement()
    model.default.joint.damping = 2
    thigh = model.worldbody.add("body")
    hip = thigh.add("joint", axis=[0, 0, 1])
    thigh.add("geom", type="capsule", fromto=[0, 0, 0, 0.1, 0, 0], size=[0.025])
    shin = thigh.add("body", pos=[0.1, 0, 0])
    knee = shin.add("joint", axis=[0, 1, 0])
    shin.add("geom", type="capsule", fromto=[0, 0, 0, 0, 0, -0.1], size=[0.02])
    model.actuator.add("position", joint=hip, kp=10)
    model.actuator.add("position", joint=knee, kp=10)
    return model


# -- copies ------------------------------------------------------------------------------------


def test_copy_of_a_model_is_an_independent_deep_copy() -> None:
    model = mjcf.from_path(GYM_ASSETS / "humanoid.xml")
    for duplicate in (copy.copy(model), copy.deepcopy(model)):
        assert duplicate is not model and duplicate.is_same_as(model)
        duplicate.find("body", "torso").pos = [0, 0, 2]
        assert model.find("body", "torso").pos.tolist() == [0, 0, 1.4]
        assert duplicate.find("joint", "abdomen_y").root is duplicate
    with pytest.raises(TypeError, match="copy the model"):
        copy.copy(model.find("body", "torso"))


# -- is_same_as ----------------------------------------------------------------------------------


def test_is_same_as_compares_values_not_spelling() -> None:
    parsed = mjcf.from_xml_string(
        """<mujoco><worldbody><body name="b" pos="0 0 1.0"><joint name="j"/>
        <geom size=".1"/><site name="s"/></body></worldbody>
        <actuator><motor joint="j"/></actuator></mujoco>"""
    )
    built = mjcf.RootElement(model="another name")  # a model's name is not compared
    body = built.worldbody.add("body", name="b", pos=[0, 0, 1])
    hinge = body.add("joint", name="j")
    body.add("site", name="s")  # sites and geoms interleave freely
    body.add("geom", size=[0.1])
    built.actuator.add("motor", joint=hinge)  # an element, where the file has a name
    assert built.is_same_as(parsed) and parsed.is_same_as(built)
    assert built.find("body", "b").is_same_as(parsed.find("body", "b"))
    built.actuator.motor[0].gear = [2]
    assert not built.is_same_as(parsed)
    assert not built.worldbody.is_same_as(None) and not built.worldbody.is_same_as(built.asset)


def test_is_same_as_orders_repeated_children_and_tendon_paths() -> None:
    def model(geom_sizes, path):
        root = mjcf.RootElement()
        body = root.worldbody.add("body", name="b")
        for size in geom_sizes:
            body.add("geom", size=[size])
        body.add("site", name="a")
        body.add("site", name="c")
        tendon = root.tendon.add("spatial", name="t")
        for site in path:
            tendon.add("site", site=site)
        return root

    assert model([0.1, 0.2], "ac").is_same_as(model([0.1, 0.2], "ac"))
    assert not model([0.1, 0.2], "ac").is_same_as(model([0.2, 0.1], "ac"))
    assert not model([0.1, 0.2], "ac").is_same_as(model([0.1, 0.2], "ca"))
    assert not model([0.1, 0.2], "ac").is_same_as(model([0.1, 0.2], "a"))


def test_is_same_as_compares_attached_models(menagerie) -> None:
    arm = mjcf.from_path(UR5E)
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    twin = copy.deepcopy(arm)
    assert twin.is_same_as(arm)
    twin.enter_scope("robotiq_2f85").find("body", "base").pos = [0, 0, 0.1]
    assert not twin.is_same_as(arm)
    assert not mjcf.from_path(UR5E).is_same_as(arm)


# -- scopes and removal ------------------------------------------------------------------------


def test_enter_scope_returns_attached_models() -> None:
    scene = mjcf.RootElement(model="scene")
    arm = mjcf.RootElement(model="arm")
    hand = mjcf.RootElement(model="hand")
    scene.attach(arm)
    arm.worldbody.add("body", name="wrist").attach(hand)
    assert scene.enter_scope("arm") is arm
    assert scene.enter_scope("arm/hand") is hand
    assert scene.find("body", "arm/wrist").enter_scope("hand") is hand  # the element's model
    assert scene.enter_scope("hand") is None and scene.enter_scope("arm/x") is None
    assert scene.enter_scope("arm/hand/") is hand  # a prefix, as dm_control takes it
    assert scene.namescope.get("body", "arm/wrist") is arm.find("body", "wrist")
    with pytest.raises(KeyError):  # dm_control's NameScope.get
        scene.namescope.get("body", "arm/elbow")


def test_sections_are_emptied_in_every_attached_model_on_request() -> None:
    """dm_control's `del model.option` / `remove(affect_attachments=True)`."""
    scene = mjcf.from_path(GYM_ASSETS / "ant.xml")
    ant = mjcf.from_path(GYM_ASSETS / "ant.xml")
    for model in (scene, ant):
        model.contact.add("exclude", body1="torso", body2="aux_1")
    scene.attach(ant)
    assert mjcf.Physics.from_mjcf_model(scene).model.nexclude == 2
    before = scene.to_xml_string()
    with pytest.raises(ValueError, match=r"remove\(affect_attachments=True\)"):
        del scene.option
    with pytest.raises(ValueError, match=r"remove\(affect_attachments=True\)"):
        scene.contact.remove()
    assert scene.to_xml_string() == before  # refused: nothing changed
    scene.option.remove(affect_attachments=True)
    scene.contact.remove(affect_attachments=True)
    for model in (scene, ant):
        assert model.option.to_xml_string(pretty_print=False) == "<option/>"
        assert model.contact.to_xml_string(pretty_print=False) == "<contact/>"
    ant_alone = mujoco.MjModel.from_xml_path(str(GYM_ASSETS / "ant.xml"))
    physics = mjcf.Physics.from_mjcf_model(scene)  # the options are MuJoCo's defaults now
    assert physics.model.opt.timestep == mujoco.MjModel.from_xml_string("<mujoco/>").opt.timestep
    assert physics.model.nexclude == 0 and ant_alone.opt.timestep != physics.model.opt.timestep


def test_element_text_forms_and_prefix_roots_as_dm_control_writes_them() -> None:
    scene = mjcf.RootElement(model="scene")
    arm = mjcf.RootElement(model="arm")
    body = arm.worldbody.add("body", name="upper")
    hinge = body.add("joint", name="shoulder", type="hinge")
    motor = arm.actuator.add("motor", joint=hinge)
    scene.attach(arm)
    assert str(body) == '<body name="upper">...</body>'  # children stand as dots
    assert str(hinge) == '<joint name="shoulder" type="hinge"/>'
    assert repr(hinge) == 'MJCF Element: <joint name="shoulder" type="hinge"/>'
    assert str(motor) == '<motor joint="shoulder"/>'  # its generated name is left out
    for prefix_root in (scene, scene.namescope):  # dm_control passes a name scope
        assert 'joint="arm/shoulder"' in motor.to_xml_string(prefix_root=prefix_root)
        assert hinge.prefixed_identifier(prefix_root) == "arm/shoulder"


def test_is_removed_after_remove_and_detach() -> None:
    model = mjcf.RootElement(model="m")
    body = model.worldbody.add("body", name="b")
    geom = body.add("geom", size=[0.1])
    child = mjcf.RootElement(model="child")
    frame = model.attach(child)
    assert not (body.is_removed or geom.is_removed or model.is_removed or frame.is_removed)
    body.remove()
    assert body.is_removed and geom.is_removed and not model.worldbody.is_removed
    child.detach()
    assert frame.is_removed and not child.is_removed


# -- generated names ------------------------------------------------------------------------------


def test_unnamed_elements_are_named_as_dm_control_names_them() -> None:
    """'/unnamed_<namespace>_<i>' after the scope prefix ('/' for the outermost model),
    i counting every element of the namespace in its model, named or not."""
    model = mjcf.RootElement(model="robot")
    first = model.worldbody.add("body")
    model.worldbody.add("body", name="named")
    third = first.add("body")  # in document order, before the named body
    geom = third.add("geom", size=[0.1])
    texture = model.asset.add("texture", type="skybox", builtin="flat", width=8, height=8)
    assert [first.full_identifier, third.full_identifier] == [
        "//unnamed_body_0",
        "//unnamed_body_1",
    ]
    assert texture.full_identifier == "//unnamed_texture_0"
    assert model.worldbody.full_identifier == "world"
    assert model.compiler.full_identifier is None  # cannot carry a name
    xml = model.to_xml_string()
    assert '<body name="//unnamed_body_0">' in xml and 'name="//unnamed_geom_0"' in xml
    assert "unnamed" not in repr(geom)  # self_only text leaves it out, as dm_control does
    scene = mjcf.RootElement(model="scene")
    scene.attach(model)
    assert third.full_identifier == "robot//unnamed_body_1"
    assert third.prefixed_identifier(model) == "//unnamed_body_1"
    assert model.worldbody.full_identifier == "robot/"  # its frame, as dm_control


def test_generated_names_work_with_mj_name2id_and_named_indexing() -> None:
    scene = mjcf.RootElement(model="scene")
    legs = [_leg() for _ in range(3)]
    for leg in legs:
        scene.attach(leg)
    physics = mjcf.Physics.from_mjcf_model(scene)
    for leg in legs:
        for element in leg.find_all("joint") + leg.find_all("geom") + leg.find_all("body"):
            kind = {"joint": 3, "geom": 5, "body": 1}[element.spec.namespace]
            index = mujoco.mj_name2id(physics.model, kind, element.full_identifier)
            assert index >= 0, element.full_identifier
        knee = leg.find_all("joint")[1]
        physics.bind(knee).qpos = 0.25
        assert physics.named.data.qpos[knee.full_identifier] == 0.25


def test_attachment_frame_joints_are_named_after_the_frame() -> None:
    scene = mjcf.RootElement(model="scene")
    leg = _leg()
    leg.worldbody.add("geom", type="sphere", size=[0.1])  # a torso, for the free body
    frame = scene.attach(leg)
    free = frame.add("freejoint")
    assert frame.full_identifier == free.full_identifier == "unnamed_model/"
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.named.data.qpos["unnamed_model/"].shape == (7,)
    slide = frame.add("joint", type="slide")
    assert slide.full_identifier == "unnamed_model//frame_joint_1"


def test_every_attached_model_may_have_frame_joints_of_the_same_names() -> None:
    """dm_control Composer gives every attached prop or walker the same frame joint
    names: each frame holds its own ('cart_1/root_x/'), and actuators refer to them."""
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", type="plane", size=[5, 5, 0.1])
    slides, motors = [], []
    for y in (-1, 1):
        cart = mjcf.RootElement(model="cart")
        cart.worldbody.add("geom", type="box", size=[0.2, 0.1, 0.05], mass=2)
        frame = scene.attach(cart)
        frame.pos = [0, y, 0.05]
        slide = frame.add("joint", name="root_x", type="slide", axis=[1, 0, 0])
        slides.append(slide)
        motors.append(scene.actuator.add("motor", name=f"push_{y}", joint=slide, gear=[10]))
    assert [s.full_identifier for s in slides] == ["cart/root_x/", "cart_1/root_x/"]
    assert scene.find("joint", "root_x") is None  # the frames' names, not the scene's
    assert 'joint="cart_1/root_x/"' in motors[1].to_xml_string()
    with pytest.raises(mjcf.NameClashError, match="'root_x' is already used"):
        slides[0].parent.add("joint", name="root_x", type="slide")  # unique in its frame
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(motors[1]).ctrl = 1.0
    for _ in range(50):
        physics.step()
    assert physics.named.data.qpos["cart_1/root_x/"] > 0.01
    assert physics.bind(slides[0]).qpos == 0 and physics.bind(slides[1]).qpos > 0.01
    assert np.array_equal(physics.bind(slides).qpos, physics.named.data.qpos[:2])


def test_world_body_of_an_attached_model_is_named_after_its_frame() -> None:
    scene = mjcf.RootElement(model="scene")
    body = scene.worldbody.add("body", name="base", pos=[0, 0, 1])
    child = mjcf.RootElement(model="child")
    child.worldbody.add("geom", size=[0.1])
    frame = body.attach(child)
    assert child.worldbody.full_identifier == "child/"  # as dm_control
    assert child.worldbody.prefixed_identifier(child) == "world"  # in its own output
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.bind(child.worldbody).xpos.tolist() == [0, 0, 1]  # the body it is in
    frame.add("joint", name="slide", type="slide")  # now the frame is a body
    assert child.worldbody.full_identifier == "child/"


def test_generated_names_read_back_unnamed() -> None:
    model = _leg()
    reread = mjcf.from_xml_string(model.to_xml_string())
    assert reread.is_same_as(model)
    assert reread.find_all("joint")[0].name is None
    assert reread.actuator.position[0].joint is reread.find_all("joint")[0]
    assert reread.to_xml_string() == model.to_xml_string()


def test_reload_follows_unnamed_joints_by_element_when_names_shift() -> None:
    scene = mjcf.RootElement(model="scene")
    leg = _leg()
    scene.attach(leg)
    physics = mjcf.Physics.from_mjcf_model(scene)
    knee = leg.find_all("joint")[1]
    physics.bind(knee).qpos = 0.3
    hip_body = leg.find_all("body")[0]
    hip_body.insert("joint", 0, axis=[1, 0, 0])  # every generated joint name shifts by one
    physics.reload_from_mjcf_model(scene, keep_state=True)
    assert physics.bind(knee).qpos[0] == 0.3
    assert physics.bind(hip_body.joint[0]).qpos[0] == 0.0


# -- same-named models ----------------------------------------------------------------------------


def test_models_of_one_name_attach_as_name_1_name_2() -> None:
    scene = mjcf.RootElement(model="scene")
    legs = [_leg() for _ in range(3)]
    for leg in legs:
        scene.attach(leg)
    assert [leg.model for leg in legs] == ["unnamed_model", "unnamed_model_1", "unnamed_model_2"]
    assert scene.enter_scope("unnamed_model_1") is legs[1]
    legs[1].detach()
    assert legs[1].model == "unnamed_model_1"  # the rename stays, as in dm_control
    again = _leg()
    scene.attach(again)
    assert again.model == "unnamed_model_1"
    mjcf.Physics.from_mjcf_model(scene)


def test_same_robot_file_twice(menagerie) -> None:
    scene = mjcf.RootElement(model="scene")
    first, second = mjcf.from_path(ROBOTIQ), mjcf.from_path(ROBOTIQ)
    scene.attach(first).pos = [0, -0.3, 0]
    scene.attach(second).pos = [0, 0.3, 0]
    assert second.model == "robotiq_2f85_1"
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.model.nu == 2
    assert physics.bind(second.find("actuator", "fingers_actuator")).ctrl.shape == ()


# -- settings of composed models -----------------------------------------------------------------


def test_size_capacities_merge_to_the_largest_memory_in_bytes() -> None:
    parent, child = mjcf.RootElement(model="p"), mjcf.RootElement(model="c")
    parent.size.memory = "2M"
    child.size.memory = "1500K"
    parent.size.nkey = 1
    child.size.nkey = 3
    child.size.nuserdata = 5
    parent.attach(child)
    # The parent holds what its models need at once, memory in bytes, as in dm_control.
    assert (parent.size.memory, parent.size.nkey, parent.size.nuserdata) == ("2097152", 3, 5)
    assert 'memory="2097152" nkey="3" nuserdata="5"' in parent.to_xml_string()
    physics = mjcf.Physics.from_mjcf_model(parent)
    assert physics.model.narena == 2 * 2**20
    other = mjcf.RootElement(model="o")
    other.size.memory = "3m"
    parent.attach(other)
    assert parent.size.memory == str(3 * 2**20)
    assert mjcf.Physics.from_mjcf_model(parent).model.narena == 3 * 2**20


def test_other_setting_conflicts_still_raise() -> None:
    parent, child = mjcf.RootElement(model="p"), mjcf.RootElement(model="c")
    parent.option.timestep = 0.002
    child.option.timestep = 0.005  # merges to the smaller
    parent.option.gravity = [0, 0, -9.81]
    child.option.gravity = [0, 0, -1.62]
    with pytest.raises(mjcf.AttachmentError, match="Conflicting values for attribute `gravity`"):
        parent.attach(child)


# -- errors dm_control code catches -----------------------------------------------------------


def test_unknown_namespace_is_a_value_error_and_still_a_key_error() -> None:
    model = mjcf.from_path(GYM_ASSETS / "ant.xml")
    for call in (lambda: model.find("bdy", "torso"), lambda: model.find_all("jiont")):
        with pytest.raises(ValueError, match="not a valid namespace") as caught:
            call()
        assert isinstance(caught.value, mjcf.NamespaceError)
        assert isinstance(caught.value, mjcf.NotFoundError) and isinstance(caught.value, KeyError)
    with pytest.raises(ValueError):
        model.find(3, "torso")
    with pytest.raises(ValueError, match="needs a name"):
        model.find("body", None)
    with pytest.raises(KeyError):  # a missing name in an element list stays a KeyError
        model.worldbody.body["nope"]
    with pytest.raises(AttributeError):
        model.find("body", "torso").poss = np.zeros(3)


# -- section lists ---------------------------------------------------------------------------------


def test_section_lists_include_attached_models_as_in_dm_control() -> None:
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("body", name="post").add("joint", name="slide", type="slide")
    scene.actuator.add("motor", name="push", joint="slide")
    legs = [_leg(), _leg()]
    for leg in legs:
        scene.attach(leg)
    positions = scene.actuator.position
    assert positions == legs[0].actuator.position + legs[1].actuator.position
    assert scene.actuator.all_children() == [scene.actuator.motor[0], *positions]
    name = positions[3].prefixed_identifier(scene)
    assert name == "unnamed_model_1//unnamed_actuator_1" and positions[name] is positions[3]
    assert scene.actuator.motor["push"].joint is scene.find("joint", "slide")
    assert [b.name for b in scene.worldbody.body] == ["post"]  # the world body: its own
    assert legs[0].actuator.position == legs[0].actuator.get_children("position")
    with pytest.raises(KeyError):
        scene.actuator.motor["unnamed_model/push"]


# -- dm_control's own examples, with `import mjcf` -------------------------------------------------


def test_dm_control_readme_flow() -> None:
    """The steps of dm_control's PyMJCF README: parse, traverse, edit, find, attach."""
    model = mjcf.from_xml_string(
        """<mujoco model="test">
          <default><default class="brick"><geom rgba="1 0 0 1"/></default></default>
          <worldbody><body name="foo"><freejoint/><inertial pos="0 0 0" mass="1"/>
            <body name="bar"><joint name="my_hinge" type="hinge"/>
              <geom name="my_geom" pos="0 1 2" class="brick"/></body></body></worldbody>
        </mujoco>"""
    )
    my_geom = model.worldbody.body["foo"].body["bar"].geom["my_geom"]
    assert my_geom.pos.tolist() == [0, 1, 2] and my_geom.rgba is None
    assert model.default.default["brick"].geom.rgba.tolist() == [1, 0, 0, 1]
    assert model.find("geom", "my_geom") is my_geom
    joints = model.find_all("joint")
    assert [j.tag for j in joints] == ["freejoint", "joint"]
    with pytest.raises(ValueError):
        my_geom.pos = [1, 2, 3, 4, 5, 6]
    with pytest.raises(ValueError):
        del model.find("body", "foo").inertial.mass
    with pytest.raises(ValueError):
        model.find("body", "foo").add("geom", name="my_geom")
    model.actuator.add("velocity", joint=model.find("joint", "my_hinge"))
    arena = mjcf.RootElement()
    arena.worldbody.add("geom", name="ground", type="plane", size=[10, 10, 1])
    arena.attach(model)
    assert arena.find("attachment_frame", "test") is mjcf.traversal_utils.get_attachment_frame(
        model
    )
    assert 'name="test/my_geom"' in arena.to_xml_string()


def test_dm_control_tutorial_creatures() -> None:
    """dm_control's tutorial: six unnamed creatures of unnamed legs, all called
    'unnamed_model', attached with free joints, driven through bound actuators."""
    rng = np.random.RandomState(42)

    def creature(num_legs: int) -> mjcf.RootElement:
        model = mjcf.RootElement()
        model.compiler.angle = "radian"
        model.worldbody.add(
            "geom", name="torso", type="ellipsoid", size=[0.1, 0.1, 0.05], rgba=rng.rand(4)
        )
        for i in range(num_legs):
            theta = 2 * i * np.pi / num_legs
            site = model.worldbody.add(
                "site", pos=[0.1 * np.cos(theta), 0.1 * np.sin(theta), 0], euler=[0, 0, theta]
            )
            site.attach(_leg())
        return model

    arena = mjcf.RootElement()
    checker = arena.asset.add("texture", type="2d", builtin="checker", width=300, height=300)
    grid = arena.asset.add("material", name="grid", texture=checker, texrepeat=[5, 5])
    arena.worldbody.add("geom", type="plane", size=[2, 2, 0.1], material=grid)
    creatures = [creature(n) for n in (3, 4, 5, 6)]
    for i, model in enumerate(creatures):
        spawn = arena.worldbody.add("site", pos=[i * 0.5, 0, 0.15], group=3)
        spawn.attach(model).add("freejoint")
    physics = mjcf.Physics.from_mjcf_model(arena)
    actuators = [a for model in creatures for a in model.find_all("actuator")]
    assert len(actuators) == 2 * (3 + 4 + 5 + 6)
    torsos = [model.find("geom", "torso") for model in creatures]
    start = physics.bind(torsos).xpos.copy()
    while physics.data.time < 0.5:
        physics.bind(actuators).ctrl = 0.9 * np.sin(5 * physics.data.time + np.arange(36))
        physics.step()
    assert not np.allclose(physics.bind(torsos).xpos, start)


def test_an_unnamed_element_added_after_compiling_is_not_bound_to_another() -> None:
    """Generated names shift when an element is added before others: the compiled
    model is found by element, never by a name now meaning something else."""
    model = _leg()
    physics = mjcf.Physics.from_mjcf_model(model)
    thigh = model.find_all("body")[0]
    before = model.worldbody.insert("body", 0, pos=[1, 0, 0])
    assert before.full_identifier == "//unnamed_body_0" and thigh.full_identifier.endswith("_1")
    with pytest.raises(mjcf.BindingError, match="added after the model was compiled"):
        physics.bind(before)
    assert physics.bind(thigh).xpos.tolist() == physics.data.xpos[1].tolist()


def test_composite_is_refused_naming_what_builds_it_in_mujoco_4() -> None:
    """dm_control's cable is a <composite>, which MuJoCo 4 removed: refused with what
    replaces it, changing nothing; a 1-D <flexcomp> cable built so simulates through
    mjcf exactly as MuJoCo simulates its text."""
    root = mjcf.RootElement()
    empty = root.to_xml_string()
    with pytest.raises(mjcf.SchemaError, match=r"MuJoCo 4 has no <composite>.*<flexcomp>"):
        root.worldbody.add("composite", type="cable", count=[41, 1, 1], size=[1, 0, 0])
    assert root.to_xml_string() == empty
    with pytest.raises(mjcf.SchemaError, match=r"MuJoCo 4 has no <composite>"):
        mjcf.from_xml_string('<mujoco><worldbody><composite type="cable"/></worldbody></mujoco>')
    cable = root.worldbody.add(
        "flexcomp", name="cable", type="grid", count=[21, 1, 1], spacing=[0.05, 1, 1],
        dim=1, pos=[0, 0, 1], radius=0.01,
    )  # fmt: skip
    cable.add("edge", equality="true")
    physics = mjcf.Physics.from_mjcf_model(root)
    reference = mujoco.MjModel.from_xml_string(root.to_xml_string())
    data = mujoco.MjData(reference)
    for _ in range(20):
        physics.step()
        mujoco.mj_step(reference, data)
    mujoco.mj_forward(reference, data)
    assert np.array_equal(physics.named.data.xpos.array, data.xpos)
    assert np.array_equal(physics.data.flexvert_xpos, data.flexvert_xpos)
