"""Physics: construction, stepping, reset, copies, pickling, divergence and rendering."""

from __future__ import annotations

import json
import os
import pickle
import platform
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import gymnasium
import mujoco
import numpy as np
import pytest

from mjcf import errors
from mjcf.physics import Physics
from tests.conftest import UR5E

Obj = mujoco.mjtObj
REPO = Path(__file__).resolve().parents[2]
GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
HUMANOID = GYM_ASSETS / "humanoid.xml"
MUJOCO_TESTDATA = Path(mujoco.__file__).parent / "testdata" / "model.xml"

TWO_KEYS = """
<mujoco>
  <worldbody>
    <body>
      <joint name="hinge" axis="0 1 0"/>
      <geom type="capsule" size="0.1" fromto="0 0 0 0 0 -1"/>
    </body>
  </worldbody>
  <keyframe>
    <key name="up" qpos="3.0"/>
    <key name="side" qpos="1.5" qvel="2"/>
  </keyframe>
</mujoco>
"""


class TaskPhysics(Physics):
    """A subclass with its own state, as composer's will have."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        super().__init__(model, data)
        self.label = "task"


def randomized(physics: Physics, seed: int = 0) -> Physics:
    rng = np.random.default_rng(seed)
    physics.data.ctrl[:] = rng.uniform(-0.5, 0.5, size=physics.model.nu)
    physics.data.qvel[:] = rng.normal(scale=0.2, size=physics.model.nv)
    physics.step(30)
    return physics


def test_constructors(tmp_path):
    from_path = Physics.from_xml_path(HUMANOID)
    assert from_path.model.nq == 24 and isinstance(from_path.data, mujoco.MjData)
    from_string = Physics.from_xml_string(HUMANOID.read_text())
    assert from_string.model.nbody == from_path.model.nbody
    assert Physics.from_xml_string(HUMANOID.read_bytes()).model.nu == 17
    mesh = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n"
    with_assets = Physics.from_xml_string(
        '<mujoco><asset><mesh file="tet.obj"/></asset>'
        '<worldbody><geom type="mesh" mesh="tet"/></worldbody></mujoco>',
        assets={"tet.obj": mesh},
    )
    assert with_assets.model.nmesh == 1 and with_assets.model.mesh_vertnum[0] == 4
    mjb = tmp_path / "humanoid.mjb"
    mujoco.mj_saveModel(from_path.model, str(mjb))
    assert Physics.from_binary_path(mjb).model.nq == 24
    shared = Physics.from_model(from_path.model)
    assert shared.model is from_path.model and shared.data is not from_path.data
    assert TaskPhysics.from_xml_path(HUMANOID).label == "task"
    # from_* forwards, so derived quantities are valid right away
    assert from_path.named.data.xpos["torso"][2] == pytest.approx(1.4)


def test_compile_errors_are_mjcf_errors():
    with pytest.raises(errors.CompileError, match="MuJoCo could not load the model"):
        Physics.from_xml_string("<mujoco><worldbody><geom type='nonsense'/></worldbody></mujoco>")
    with pytest.raises(errors.CompileError):
        Physics.from_xml_path("/nonexistent/model.xml")


def test_step_forward_time_and_timestep():
    physics = Physics.from_xml_path(HUMANOID)
    assert physics.timestep() == pytest.approx(physics.model.opt.timestep)
    assert physics.time() == 0.0
    physics.step()
    physics.step(nstep=9)
    assert physics.time() == pytest.approx(10 * physics.timestep())
    physics.data.qpos[2] = 2.0
    physics.forward()
    assert physics.data.xpos[1, 2] == pytest.approx(2.0)


def test_reset_to_qpos0_and_to_keyframes():
    physics = Physics.from_xml_string(TWO_KEYS)
    physics.step(20)
    physics.reset()
    assert physics.time() == 0.0 and physics.data.qpos[0] == 0.0
    physics.reset(keyframe="side")
    assert physics.data.qpos[0] == 1.5 and physics.data.qvel[0] == 2.0
    physics.reset(keyframe=0)
    assert physics.data.qpos[0] == 3.0
    # reset forwards: derived quantities match the keyframe
    assert physics.data.xpos[1] == pytest.approx([0, 0, 0])
    assert physics.data.geom_xpos[0][0] == pytest.approx(np.sin(3.0) * -0.5, abs=1e-9)
    with pytest.raises(errors.NotFoundError, match=r"no keyframe named 'sid' \(did you mean"):
        physics.reset(keyframe="sid")
    with pytest.raises(errors.NotFoundError, match="has 2 keyframes"):
        physics.reset(keyframe=2)


def test_reset_ur5e_home_keyframe():
    physics = Physics.from_xml_path(UR5E)
    physics.reset(keyframe="home")
    assert np.array_equal(physics.data.qpos, physics.model.key_qpos[0])
    assert np.array_equal(physics.data.ctrl, physics.model.key_ctrl[0])


def test_reset_context_resets_then_forwards():
    physics = randomized(Physics.from_xml_path(HUMANOID))
    with physics.reset_context() as same:
        assert same is physics and physics.time() == 0.0
        physics.named.data.qpos["root"][2] = 3.0
    assert physics.named.data.xpos["torso"][2] == pytest.approx(3.0)
    with pytest.raises(errors.PhysicsError), physics.reset_context():
        physics.data.qvel[0] = np.inf


def test_copy_shares_or_copies_the_model():
    physics = randomized(TaskPhysics.from_xml_path(HUMANOID))
    physics.label = "copied along"
    clone = physics.copy()
    assert type(clone) is TaskPhysics and clone.label == "copied along"
    assert clone.model is physics.model and clone.data is not physics.data
    assert np.array_equal(clone.data.qpos, physics.data.qpos)
    assert np.array_equal(clone.data.xpos, physics.data.xpos)
    clone.step(5)
    assert clone.time() != physics.time()
    deep = physics.copy(share_model=False)
    assert deep.model is not physics.model
    deep.model.body_mass[1] = 99.0
    assert physics.model.body_mass[1] != 99.0
    physics.step(10)
    deep.model.body_mass[1] = physics.model.body_mass[1]
    deep.step(10)
    assert np.array_equal(deep.data.qpos, physics.data.qpos)


@pytest.mark.parametrize("path", [HUMANOID, MUJOCO_TESTDATA], ids=["humanoid", "testdata"])
def test_pickle_round_trip_gives_the_same_next_100_steps(path):
    physics = randomized(TaskPhysics.from_xml_path(path))
    restored = pickle.loads(pickle.dumps(physics))
    assert type(restored) is TaskPhysics and restored.label == "task"
    assert restored.time() == physics.time()
    for field in ("qpos", "qvel", "act", "ctrl", "qacc_warmstart"):
        assert np.array_equal(getattr(restored.data, field), getattr(physics.data, field)), field
    rng = np.random.default_rng(7)
    for _ in range(100):
        physics.data.ctrl[:] = restored.data.ctrl[:] = rng.uniform(-1, 1, physics.model.nu)
        physics.step()
        restored.step()
        assert np.array_equal(restored.data.qpos, physics.data.qpos)
        assert np.array_equal(restored.data.qvel, physics.data.qvel)
    assert np.array_equal(restored.data.sensordata, physics.data.sensordata)


def test_huge_velocity_raises_physics_error(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo logs its warnings to MUJOCO_LOG.TXT in the cwd
    physics = Physics.from_xml_path(HUMANOID)
    physics.check_invalid_state()  # a fresh state is valid
    physics.named.data.qvel[:] = 1e12  # tracked: the step starts from this state
    physics.step()
    with pytest.raises(errors.PhysicsError, match=r"mjWARN_BADQVEL.*joint 'root'"):
        physics.check_invalid_state()
    physics.reset()
    physics.check_invalid_state()


def test_absurd_gains_diverge_inside_check_divergence(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    physics = Physics.from_xml_path(HUMANOID)
    physics.model.actuator_gainprm[:, 0] = 1e10
    physics.data.ctrl[:] = 1.0
    with pytest.raises(errors.PhysicsError, match="invalid at t="), physics.check_divergence():
        physics.step(300)
    with physics.check_divergence():  # passes once the state is valid again
        physics.reset()
        physics.model.actuator_gainprm[:, 0] = 100.0
        physics.step(10)


def test_nan_control_is_reported(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    physics = Physics.from_xml_path(HUMANOID)
    physics.data.ctrl[3] = np.nan
    physics.step()
    name = mujoco.mj_id2name(physics.model, Obj.mjOBJ_ACTUATOR, 3)
    with pytest.raises(errors.PhysicsError, match=f"mjWARN_BADCTRL.*actuator '{name}'"):
        physics.check_invalid_state()


# -- rendering: in a fresh interpreter, because MuJoCo picks its GL backend at import ---------

RENDER_SCRIPT = """
import json, sys
import numpy as np
from mjcf import errors
from mjcf.physics import Physics
physics = Physics.from_xml_path(sys.argv[1])
try:
    rgb = physics.render(120, 160)
    depth = physics.render(120, 160, depth=True)
    seg = physics.render(120, 160, segmentation=True)
    again = physics.render(120, 160)
except errors.RenderError as e:
    print(json.dumps({"error": str(e)}))
    sys.exit(0)
physics.close()
np.savez(sys.argv[2], rgb=rgb, depth=depth, seg=seg, again=again)
print(json.dumps({"backend": __import__("os").environ.get("MUJOCO_GL", "")}))
"""


def run_render(env: dict[str, str], out: Path) -> dict:
    env = {**env, "PYTHONPATH": os.pathsep.join([str(REPO), env.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-c", RENDER_SCRIPT, str(HUMANOID), str(out)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def write_png(path: Path, rgb: np.ndarray) -> None:
    """A minimal RGB8 PNG writer (zlib + the three mandatory chunks), to need no imaging lib."""

    def chunk(tag: bytes, payload: bytes) -> bytes:
        body = tag + payload
        return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body))

    height, width, _ = rgb.shape
    rows = b"".join(b"\0" + row.tobytes() for row in np.ascontiguousarray(rgb, np.uint8))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(rows))
        + chunk(b"IEND", b"")
    )


def test_render_writes_a_non_blank_png(tmp_path):
    env = dict(os.environ)
    env.setdefault("MUJOCO_GL", "egl")
    result = run_render(env, tmp_path / "frames.npz")
    if "error" in result:
        assert "no OpenGL backend" in result["error"], result["error"]
        pytest.skip(f"no GL backend on this machine: {result['error']}")
    frames = np.load(tmp_path / "frames.npz")
    rgb, depth, seg = frames["rgb"], frames["depth"], frames["seg"]
    assert rgb.shape == (120, 160, 3) and rgb.dtype == np.uint8
    assert rgb.std() > 10 and len(np.unique(rgb.reshape(-1, 3), axis=0)) > 50
    assert np.array_equal(frames["again"], rgb)  # the cached renderer renders the same
    assert depth.shape == (120, 160) and np.isfinite(depth).all() and np.ptp(depth) > 0.1
    assert seg.shape == (120, 160, 2) and len(np.unique(seg[..., 0])) >= 3
    png = tmp_path / "humanoid.png"
    write_png(png, rgb)
    data = png.read_bytes()
    assert data.startswith(b"\x89PNG") and len(data) > 1000
    assert struct.unpack(">II", data[16:24]) == (160, 120)


@pytest.mark.skipif(platform.system() != "Linux", reason="GLFW needs no display elsewhere")
def test_render_without_a_display_names_the_fix(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["MUJOCO_GL"] = "glfw"  # asked for explicitly: unset, a backend that works is chosen
    result = run_render(env, tmp_path / "frames.npz")
    assert "error" in result, "GLFW rendered without $DISPLAY"
    message = result["error"]
    assert "MUJOCO_GL='glfw'" in message and "$DISPLAY" in message
    assert "libegl1 libegl-mesa0 libgl1" in message and "libosmesa6" in message


def test_render_request_errors():
    physics = Physics.from_xml_path(HUMANOID)
    with pytest.raises(errors.RenderError, match="framebuffer") as raised:
        physics.render(1, 100_000)  # wider than any OpenGL buffer (10,000 x 10,000 is 1.5 GB)
    # The size is at fault, not the backend, which made its context.
    message = str(raised.value)
    assert message.startswith("a frame of 1 x 100000 pixels (height x width) cannot be drawn")
    assert "GL_MAX_RENDERBUFFER_SIZE" in message and "offsamples" in message
    assert "Unset MUJOCO_GL" not in message and "apt-get" not in message


@pytest.mark.parametrize(
    "first_use",
    [
        lambda p: p.data.xpos.copy(),
        lambda p: p.named.data.xpos["torso"].copy(),
        lambda p: p.bind_names(Obj.mjOBJ_BODY, "torso").xpos.copy(),
        lambda p: p.copy().data.xpos.copy(),
        lambda p: pickle.loads(pickle.dumps(p)).data.xpos.copy(),
        lambda p: (p.step(), p.data.xpos.copy())[1],
        lambda p: p.get_state(),
    ],
)
def test_a_new_physics_is_forwarded_whatever_is_used_first(first_use) -> None:
    """The MjData a physics makes on first use (not when it is made) is the forwarded
    data an eager one would have had."""
    model = mujoco.MjModel.from_xml_path(str(HUMANOID))
    eager = mujoco.MjData(model)
    mujoco.mj_forward(model, eager)
    expected = first_use(Physics(model, eager))
    np.testing.assert_array_equal(first_use(Physics.from_model(model)), expected)
