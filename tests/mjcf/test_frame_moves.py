"""Moving a frame through its binding equals compiling the model with the frame there.

A frame without joints (an attachment frame, a `<frame>`) compiles to a MuJoCo `<frame>`
folded into what it holds; `physics.bind(frame).pos = ...` moves everything it holds.
Each case writes a frame's pose through the binding, then compares the whole simulation
(every body's, geom's, site's, camera's and light's world pose, every model array, the
frames' bindings, the state after a reset, 100 steps of a free body resting on what
moved) with a model compiled from MJCF in which the frame has that pose.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np
import pytest

import mjcf
from tests.mjcf.compare import model_differences

_WORLD = ("xpos", "xmat", "xquat", "geom_xpos", "geom_xmat", "site_xpos", "site_xmat",
          "cam_xpos", "cam_xmat", "light_xpos", "light_xdir", "xanchor", "xaxis", "qpos",
          "mocap_pos", "mocap_quat")  # fmt: skip


def _quat(euler_degrees: list[float]) -> np.ndarray:
    quat = np.empty(4)
    mujoco.mju_euler2Quat(quat, np.radians(euler_degrees), "xyz")
    return quat


def _compose(outer: tuple, inner: tuple) -> tuple[np.ndarray, np.ndarray]:
    pos, quat = np.empty(3), np.empty(4)
    mujoco.mju_mulPose(pos, quat, *outer, *inner)
    return pos, quat


def _inverse(pose: tuple) -> tuple[np.ndarray, np.ndarray]:
    pos, quat = np.empty(3), np.empty(4)
    mujoco.mju_negPose(pos, quat, *pose)
    return pos, quat


def _contents(model: mjcf.RootElement, name: str) -> None:
    """A body (with a hinge and a geom), a geom, a site, a camera and a light at the top
    level of `model`, turned and offset so that every orientation shows."""
    body = model.worldbody.add("body", name=f"{name}_body", pos=[0.1, 0.2, 0.3],
                               euler=[10, 20, 30])  # fmt: skip
    body.add("joint", name=f"{name}_hinge", axis=[0, 1, 0])
    body.add("geom", size=[0.05], pos=[0.1, 0, 0])
    body.add("site", name=f"{name}_inner_site", pos=[0, 0.1, 0])
    model.worldbody.add("geom", name=f"{name}_geom", type="box", size=[0.1, 0.2, 0.05],
                        pos=[-0.3, 0.1, 0], euler=[0, 15, 0])  # fmt: skip
    model.worldbody.add("site", name=f"{name}_site", pos=[0, -0.4, 0.1], zaxis=[1, 1, 0])
    model.worldbody.add("camera", name=f"{name}_camera", pos=[0.5, 0, 0.5],
                        xyaxes=[0, 1, 0, -1, 0, 1])  # fmt: skip
    model.worldbody.add("light", name=f"{name}_light", pos=[0, 0, 2], dir=[0.3, 0, -1])


@dataclass
class Scene:
    """A scene built for one case, and the elements the case moves and reads."""

    root: mjcf.RootElement
    frames: dict[str, mjcf.Element]  # the frames of the scene whose bindings are compared
    target: str  # the frame the case moves
    parent: tuple[np.ndarray, np.ndarray] | None = None  # the target's parent frame's offset


def _attached(angle: str, place: str) -> Callable[[], Scene]:
    """A child with all kinds of contents, a free body and a mocap body at its top level,
    a `<frame>` holding a geom and a grandchild attached inside it, attached without
    joints at a turned site of the world body or of a body swung on a hinge."""

    def build() -> Scene:
        scene = mjcf.RootElement(model="scene")
        scene.compiler.angle = angle
        unit = 1.0 if angle == "degree" else np.pi / 180
        scene.worldbody.add("geom", name="floor", type="plane", size=[5, 5, 0.1])
        holder = scene.worldbody
        if place == "body":
            holder = scene.worldbody.add("body", name="arm", pos=[0, 0, 1],
                                         euler=[0, 0, 30 * unit])  # fmt: skip
            holder.add("joint", name="swing", axis=[0, 1, 0])
            holder.add("inertial", pos=[0, 0, 0], mass=1, diaginertia=[0.1, 0.1, 0.1])
        site = holder.add("site", name="mount", pos=[1, 2, 3], euler=[30 * unit, 0, 45 * unit])
        child = mjcf.RootElement(model="child")
        child.compiler.angle = "degree"
        _contents(child, "child")
        if place == "world":  # free bodies and mocap bodies are in the world only
            ball = child.worldbody.add("body", name="ball", pos=[0, 0, 0.5])
            ball.add("freejoint")
            ball.add("geom", size=[0.05], mass=0.1)
            child.worldbody.add("body", name="target", mocap=True, pos=[0.2, 0, 0])
        inner = child.worldbody.add("frame", name="inner", pos=[0, 0, 0.5], euler=[0, 0, 60])
        inner.add("geom", name="in_frame", size=[0.05], pos=[0.2, 0, 0])
        grandchild = mjcf.RootElement(model="grandchild")
        _contents(grandchild, "grandchild")
        inner_attachment = inner.attach(grandchild)
        inner_attachment.pos = [0.3, 0, 0]
        frame = site.attach(child)
        frames = {
            "frame": frame,
            "child world": child.worldbody,
            "inner": inner,
            "grandchild": inner_attachment,
            "grandchild world": grandchild.worldbody,
        }
        return Scene(scene, frames, "frame")

    return build


def _nested(target: str) -> Callable[[], Scene]:
    """A scene `<frame>` in the world body (angles in degrees) holding a `<frame>` with
    contents and a model attached inside it; `target` is the one the case moves."""

    def build() -> Scene:
        scene = mjcf.RootElement(model="scene")
        outer_pose = ([0.5, -0.5, 0.2], [20, -10, 35])
        outer = scene.worldbody.add("frame", name="outer", pos=outer_pose[0], euler=outer_pose[1])
        inner = outer.add("frame", name="inner", pos=[0, 0.3, 0.1], euler=[45, 0, 0])
        _contents_of_frame(inner)
        child = mjcf.RootElement(model="child")
        _contents(child, "child")
        frame = inner.attach(child)
        frames = {"outer": outer, "inner": inner, "frame": frame, "child world": child.worldbody}
        parent = None
        if target == "inner":
            parent = (np.array(outer_pose[0], dtype=float), _quat(outer_pose[1]))
        return Scene(scene, frames, target, parent)

    return build


def _in_a_body() -> Scene:
    """A `<frame>` in a body holding the body's hinge, inertial, a geom and a site (the
    frame moves where the body turns, and its mass)."""
    scene = mjcf.RootElement(model="scene")
    link = scene.worldbody.add("body", name="link", pos=[0, 0, 1], euler=[0, 20, 0])
    link.add("geom", name="link_geom", type="capsule", fromto=[0, 0, 0, 0.5, 0, 0], size=[0.05])
    mount = link.add("frame", name="mount", pos=[0.1, 0.2, 0], euler=[10, 0, 30])
    mount.add("joint", name="swing", axis=[0, 1, 0.5])
    mount.add("inertial", pos=[0.2, 0, 0], mass=2, diaginertia=[0.1, 0.2, 0.3], euler=[0, 0, 15])
    mount.add("geom", name="mount_geom", type="box", size=[0.1, 0.05, 0.02], pos=[0.3, 0, 0])
    mount.add("site", name="mount_site", pos=[0.5, 0, 0])
    link.add("body", name="tip", pos=[0.5, 0, 0]).add("geom", size=[0.03])
    return Scene(scene, {"mount": mount}, "mount")


def _contents_of_frame(frame: mjcf.Element) -> None:
    frame.add("body", name="body_in_frame", pos=[0, 0, 0.2]).add("geom", size=[0.05])
    frame.add("geom", name="geom_in_frame", size=[0.05], pos=[0.1, 0, 0])
    frame.add("site", name="site_in_frame", euler=[0, 90, 0])
    frame.add("camera", name="camera_in_frame", pos=[0, 0, 1])
    frame.add("light", name="light_in_frame", pos=[0, 0, 2], dir=[0, 1, -1])


CASES = {
    "attached at the world body, degrees": _attached("degree", "world"),
    "attached at the world body, radians": _attached("radian", "world"),
    "attached inside a moved body": _attached("degree", "body"),
    "a nested <frame>": _nested("inner"),
    "the <frame> around it": _nested("outer"),
    "a <frame> holding a joint and an inertial": _in_a_body,
}
# New poses: (position, euler angles in degrees): a non-trivial orientation.
POSES = [([0.4, -1.2, 0.7], [25, -40, 110]), ([0, 0, 0], [0, 0, 0])]


def _place(scene: Scene, pos: np.ndarray, quat: np.ndarray, euler: list[float]) -> None:
    """Give the target frame of `scene` the offset (pos, quat) from its body in the MJCF:
    in degrees when it has no parent frame, else as a quaternion relative to that frame."""
    frame = scene.frames[scene.target]
    for name in ("pos", "quat", "euler", "axisangle", "xyaxes", "zaxis"):
        if getattr(frame, name) is not None:
            delattr(frame, name)
    if scene.parent is None:
        frame.pos = pos
        angle = frame.root.compiler.angle or "degree"
        frame.euler = euler if angle == "degree" else np.radians(euler)
    else:
        frame.pos, frame.quat = _compose(_inverse(scene.parent), (pos, quat))


def _physics(scene: Scene) -> mjcf.Physics:
    physics = mjcf.Physics.from_mjcf_model(scene.root)
    swing = scene.root.find("joint", "swing")
    if swing is not None:
        physics.bind(swing).qpos = 0.7  # the body the frame is in is moved
    return physics


def _assert_same(moved: mjcf.Physics, moved_scene: Scene, expected: mjcf.Physics,
                 expected_scene: Scene) -> None:  # fmt: skip
    """The world poses of everything in MjData (up to date: the caller forwards), and
    what bindings read."""
    for field in _WORLD:
        np.testing.assert_allclose(getattr(moved.data, field), getattr(expected.data, field),
                                   atol=1e-12, err_msg=field)  # fmt: skip
    _assert_same_bindings(moved, moved_scene, expected, expected_scene)


def _assert_same_bindings(moved: mjcf.Physics, moved_scene: Scene, expected: mjcf.Physics,
                          expected_scene: Scene) -> None:  # fmt: skip
    """What bindings read (each brings the physics up to date first): the world poses of
    every body, geom, site, camera and light, and the frames' poses."""
    for tag in ("body", "geom", "site", "camera", "light"):
        mine = moved.bind(moved_scene.root.find_all(tag))
        theirs = expected.bind(expected_scene.root.find_all(tag))
        for field in ("xpos", "xmat") if tag != "light" else ("xpos", "xdir"):
            np.testing.assert_allclose(getattr(mine, field), getattr(theirs, field), atol=1e-12,
                                       err_msg=f"{field} of {tag}s")  # fmt: skip
    for name, frame in moved_scene.frames.items():
        mine, theirs = moved.bind(frame), expected.bind(expected_scene.frames[name])
        for field in ("pos", "quat", "xpos", "xquat", "xmat"):
            np.testing.assert_allclose(getattr(mine, field), getattr(theirs, field), atol=1e-12,
                                       err_msg=f"{field} of {name}")  # fmt: skip


@pytest.mark.parametrize("pose", POSES, ids=["turned", "identity"])
@pytest.mark.parametrize("case", CASES)
def test_writing_a_frame_pose_equals_compiling_it_there(case: str, pose: tuple) -> None:
    position, euler = np.array(pose[0], dtype=float), pose[1]
    quat = _quat(euler)
    scene = CASES[case]()
    physics = _physics(scene)
    bound = physics.bind(scene.frames[scene.target])
    before = bound.xpos.copy()
    bound.pos = position
    bound.quat = quat
    np.testing.assert_allclose(bound.pos, position, atol=1e-15)
    np.testing.assert_allclose(bound.quat, quat, atol=1e-15)
    expected_scene = CASES[case]()
    _place(expected_scene, position, quat, euler)
    expected = _physics(expected_scene)
    if pose is POSES[0]:
        assert not np.allclose(before, expected.bind(expected_scene.frames[scene.target]).xpos)
    _assert_same_bindings(physics, scene, expected, expected_scene)  # before forward()
    physics.forward()
    _assert_same(physics, scene, expected, expected_scene)
    # mj_setConst refits the boxes of each body's midphase tree over its moved geoms; the
    # compiler would also split them otherwise. Culling only: contacts are the same
    # (they are sorted), which the simulation below shows with geoms moved far.
    differences = model_differences(expected.model, physics.model)
    assert [d for d in differences if not d.startswith(("bvh_aabb", "bvh_nodeid"))] == []
    physics.reset()  # the free body's qpos0, the mocap body's pose: as compiled there
    expected.reset()
    _assert_same(physics, scene, expected, expected_scene)


def _table(pose: tuple | None = None) -> tuple[mjcf.RootElement, mjcf.Element]:
    """A floor; a table (a model of top-level geoms) attached without joints, a free box
    (two geoms) resting on it in the same model; a free ball outside it, above where the
    table goes (`_MOVE`). With `pose`, the table's frame has it."""
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", name="floor", type="plane", size=[5, 5, 0.1])
    table = mjcf.RootElement(model="table")
    table.worldbody.add("geom", name="top", type="box", size=[0.6, 0.6, 0.02], pos=[0, 0, 0.5])
    table.worldbody.add("geom", name="leg", type="box", size=[0.02, 0.02, 0.25], pos=[0, 0, 0.25])
    box = table.worldbody.add("body", name="box", pos=[0.3, 0.1, 0.58])
    box.add("freejoint")
    box.add("geom", type="box", size=[0.05, 0.05, 0.05], mass=0.5)
    box.add("geom", type="sphere", size=[0.01], pos=[0, 0, 0.05], mass=0.01)
    ball = scene.worldbody.add("body", name="ball", pos=[1.4, 0.75, 0.59])
    ball.add("freejoint")
    ball.add("geom", size=[0.05], mass=0.2)
    frame = scene.worldbody.attach(table)
    if pose is not None:
        frame.pos, frame.quat = pose
    return scene, frame


# Far from where the table was compiled (its geoms leave the boxes MuJoCo's midphase
# culls contacts with, unless they are rebuilt), turned and tilted a little.
_MOVE = (np.array([1.5, 0.8, 0.01]), _quat([3, -2, 40]))


def test_free_bodies_resting_on_a_moved_frame_simulate_as_compiled_there() -> None:
    scene, frame = _table()
    physics = mjcf.Physics.from_mjcf_model(scene)
    physics.bind(frame).pos, physics.bind(frame).quat = _MOVE
    expected = mjcf.Physics.from_mjcf_model(_table(_MOVE)[0])
    for _ in range(100):
        physics.step()
        expected.step()
    assert physics.data.ncon == expected.data.ncon > 0
    for field in ("qpos", "qvel", "xpos", "xmat"):
        np.testing.assert_allclose(getattr(physics.data, field), getattr(expected.data, field),
                                   atol=1e-12, err_msg=field)  # fmt: skip
    ball, box = physics.data.qpos[:3], physics.data.qpos[7:10]
    assert ball[2] > 0.55 and box[2] > 0.55  # both on the table, where it was taken
    assert np.linalg.norm(box[:2] - [0.3, 0.1]) > 1
