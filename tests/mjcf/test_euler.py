"""Euler angles of an attached model whose `eulerseq` differs from its parent's become
quaternions: for every sequence MuJoCo accepts (each axis intrinsic or extrinsic), the
composed model has the orientations the child model has compiled alone."""

import itertools

import mujoco
import numpy as np
import pytest

import mjcf

SEQUENCES = ["".join(axes) for axes in itertools.product("xyzXYZ", repeat=3)]
EULER = {"radian": [0.5, -0.3, 1.1], "degree": [30.0, -20.0, 65.0]}


def _child(sequence: str, angle: str) -> mjcf.RootElement:
    child = mjcf.RootElement(model="child")
    child.compiler.set_attributes(eulerseq=sequence, angle=angle)
    body = child.worldbody.add("body", name="b", euler=EULER[angle])
    body.add("geom", name="g", size=[0.1], euler=EULER[angle][::-1])
    body.add("site", name="s", euler=[-v for v in EULER[angle]])
    return child


def _orientations(model: mujoco.MjModel, prefix: str) -> np.ndarray:
    body = model.body_quat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, prefix + "b")]
    geom = model.geom_quat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, prefix + "g")]
    site = model.site_quat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, prefix + "s")]
    return np.array([body, geom, site])


@pytest.mark.parametrize("angle", sorted(EULER))
def test_every_sequence_composes_as_mujoco_compiles_it_alone(angle: str) -> None:
    for sequence in SEQUENCES:
        alone = mjcf.Physics.from_mjcf_model(_child(sequence, angle)).model
        scene = mjcf.RootElement(model="scene")  # eulerseq 'xyz', angle 'degree'
        scene.attach(_child(sequence, angle))
        if sequence != "xyz":
            assert "euler" not in scene.to_xml_string()  # converted, not copied
        composed = mjcf.Physics.from_mjcf_model(scene).model
        np.testing.assert_allclose(
            _orientations(composed, "child/"), _orientations(alone, ""), atol=1e-12,
            err_msg=f"eulerseq={sequence!r}, angle={angle!r}",
        )  # fmt: skip
