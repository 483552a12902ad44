"""Writing a model again after a change writes the change: the text the writer keeps
for unchanged elements (and the composition it keeps for unchanged models) never
outlives what it was made from. The oracle is a copy of the model, which has no
caches, written after each change."""

from __future__ import annotations

import copy

import pytest

import mjcf


def _robot(name: str) -> mjcf.RootElement:
    model = mjcf.RootElement(model=name)
    model.compiler.angle = "radian"
    material = model.asset.add("material", name="paint", rgba=[1, 0, 0, 1])
    model.asset.add("texture", name="grid", type="2d", builtin="checker", width=8, height=8)
    body = model.worldbody.add("body", name="link", euler=[0, 0, 0.5])
    body.add("joint", name="hinge", type="hinge", range=[-1, 1])
    body.add("geom", type="box", size=[0.1, 0.1, 0.1], material=material)
    model.actuator.add("motor", joint="hinge")
    return model


def _scene() -> tuple[mjcf.RootElement, list[mjcf.RootElement]]:
    scene = mjcf.RootElement(model="scene")
    scene.compiler.angle = "degree"
    robots = [_robot("a"), _robot("b")]
    for robot in robots:
        scene.attach(robot)
    scene.worldbody.add("geom", name="marker", size=[0.1], material=robots[1].asset.material[0])
    return scene, robots


def _rename_a_material_a_scene_geom_refers_to(scene, robots):
    robots[1].find("material", "paint").name = "varnish"


def _rename_an_attached_model(scene, robots):
    robots[0].model = "renamed"


def _change_an_attached_model_angle_unit(scene, robots):
    robots[1].compiler.angle = "degree"


def _change_the_texture_another_copy_shares(scene, robots):
    robots[0].find("texture", "grid").width = 16


def _detach_a_model(scene, robots):
    robots[0].detach()


def _give_the_scene_global_defaults(scene, robots):
    scene.default.geom.rgba = [0, 0, 1, 1]


def _edit_an_array_in_place(scene, robots):
    robots[1].find("body", "link").euler[2] = 1.5


@pytest.mark.parametrize(
    "change",
    [
        _rename_a_material_a_scene_geom_refers_to,
        _rename_an_attached_model,
        _change_an_attached_model_angle_unit,
        _change_the_texture_another_copy_shares,
        _detach_a_model,
        _give_the_scene_global_defaults,
        _edit_an_array_in_place,
    ],
)
def test_a_written_then_changed_scene_writes_as_a_fresh_copy(change) -> None:
    scene, robots = _scene()
    scene.to_xml_string()
    mjcf.Physics.from_mjcf_model(scene)  # both kinds of output have kept their text
    change(scene, robots)
    fresh = copy.deepcopy(scene)
    assert scene.to_xml_string() == fresh.to_xml_string()
    ours = mjcf.Physics.from_mjcf_model(scene).model
    assert ours.names == mjcf.Physics.from_mjcf_model(fresh).model.names
