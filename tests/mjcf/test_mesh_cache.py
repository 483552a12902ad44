"""Compiling after an edit gives the model a fresh process gives, whatever MuJoCo's mesh
cache (keyed by file name) holds from earlier compiles in this process."""

from __future__ import annotations

import subprocess
import sys

import mujoco
import numpy as np
import pytest

import mjcf
from mjcf.tree import assets
from tests.conftest import MENAGERIE

PAD = MENAGERIE / "robotiq_2f85" / "assets" / "pad.stl"
# A value of each mesh attribute that changes what a mesh from PAD compiles to, or is
# refused with it; the attributes the cache compares and those it does not.
_VALUES = {
    "vertex": "0 0 0 1 0 0 0 1 0 0 0 1",
    "normal": "0 0 1",
    "texcoord": "0.5 0.5 0.1 0.2",
    "face": "0 1 2",
    "refpos": "0.1 0 0",
    "refquat": "0 1 0 0",
    "scale": "2 2 2",
    "smoothnormal": "true",
    "maxhullvert": "8",
    "inertia": "shell",
}


def _raw(extra: str = "") -> str:
    return (
        f'<mujoco><asset><mesh name="pad" file="{PAD}" {extra}/></asset><worldbody><body>'
        '<freejoint/><geom type="mesh" mesh="pad"/></body></worldbody></mujoco>'
    )


def _compiled(xml: str) -> object:
    """The mesh arrays and masses MuJoCo compiles `xml` to, or its error's first line."""
    try:
        model = mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        return str(error).splitlines()[0]
    names = ("mesh_vert", "mesh_normal", "mesh_texcoord", "mesh_face", "body_mass", "body_inertia")
    return [np.array(getattr(model, name)) for name in names]


def _same(a: object, b: object) -> bool:
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    assert isinstance(a, list) and isinstance(b, list)
    return all(x.shape == y.shape and np.allclose(x, y) for x, y in zip(a, b, strict=True))


@pytest.mark.parametrize("name", sorted(_VALUES))
def test_the_attributes_mujocos_mesh_cache_ignores_are_those_mjcf_compiles_apart(
    name: str,
) -> None:
    """MuJoCo's own compile of a mesh after the same file compiled without `name` gives
    what a fresh compile gives exactly for the attributes its cache compares."""
    cache = mujoco.mj_getCache()
    mujoco.mj_clearCache(cache)
    fresh = _compiled(_raw(f'{name}="{_VALUES[name]}"'))
    mujoco.mj_clearCache(cache)
    _compiled(_raw())
    after_cache = _compiled(_raw(f'{name}="{_VALUES[name]}"'))
    mujoco.mj_clearCache(cache)
    assert _same(fresh, after_cache) == (name not in assets.NOT_IN_MESH_CACHE_KEY)


def _model() -> tuple[mjcf.RootElement, mjcf.Element]:
    model = mjcf.RootElement()
    mesh = model.asset.add("mesh", name="pad", file=str(PAD))
    model.worldbody.add("body").add("geom", type="mesh", mesh="pad")
    return model, mesh


def test_an_edit_the_mesh_cache_ignores_is_refused_as_in_a_fresh_process() -> None:
    model, mesh = _model()
    mjcf.Physics.from_mjcf_model(model)  # MuJoCo caches the mesh of this file
    mesh.texcoord = [0.5, 0.5, 0.1, 0.2]
    with pytest.raises(mjcf.CompileError, match="texcoord must be 2\\*nv") as caught:
        mjcf.Physics.from_mjcf_model(model)
    code = (
        "import mjcf\n"
        "model = mjcf.RootElement()\n"
        f"mesh = model.asset.add('mesh', name='pad', file={str(PAD)!r})\n"
        "model.worldbody.add('body').add('geom', type='mesh', mesh='pad')\n"
        "mesh.texcoord = [0.5, 0.5, 0.1, 0.2]\n"
        "try:\n    mjcf.Physics.from_mjcf_model(model)\n"
        "except mjcf.CompileError as error:\n    print(str(error).splitlines()[0])\n"
    )
    fresh = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert fresh.stdout.strip() == str(caught.value).splitlines()[0]


def test_normals_set_after_a_compile_are_compiled_as_in_a_fresh_process() -> None:
    model, mesh = _model()
    first = mjcf.Physics.from_mjcf_model(model).model
    mesh.normal = [0, 0, 1]
    edited = mjcf.Physics.from_mjcf_model(model).model
    mujoco.mj_clearCache(mujoco.mj_getCache())
    fresh = mjcf.Physics.from_mjcf_model(model).model
    assert np.array_equal(edited.mesh_normal, fresh.mesh_normal)
    assert not np.array_equal(edited.mesh_normal, first.mesh_normal)
    del mesh.normal
    assert np.array_equal(mjcf.Physics.from_mjcf_model(model).model.mesh_normal, first.mesh_normal)
