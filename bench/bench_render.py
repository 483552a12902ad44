"""Camera frames of every shipped task against the software rasterizer's floor.

    python bench/bench_render.py                    # every task, 64x64, 84x84 and 480x640
    python bench/bench_render.py CartpoleSwingup    # some of them
    python bench/bench_render.py vector             # the vector figure alone

The floor is a plain plane and capsule without shadows (`<quality shadowsize="0"/>`) drawn
by a raw `mujoco.Renderer` made in the same run at the same size. Ours is a frame as a user
gets it: `gym.make(id, render_mode='rgb_array', width=w, height=h)`, then `env.render()`
through the task's camera (`mjcf.sim.rendering` fits the render settings to the size). Before
is a raw `mujoco.Renderer` on the same compiled model with the model's own settings,
MuJoCo's defaults (a 4096-pixel shadow map, 4x multisampling, a 640x480 buffer): what a
frame cost before the settings were fitted. Each figure is the best of rounds of process
CPU time per frame (the rasterizer's threads are the process's, and time other processes
take is not counted), the rounds of floor, ours and before alternating.

`factors` prices each render setting and part of the scene on one task at 64x64: what it
costs alone on top of our frame, in floors; and the time to make a renderer's contexts in
a new OpenGL context and in one kept from a closed renderer, as a recompile's renderers get.

`vector` draws the 64x64 frames of N = 1, 4, 16 CartpoleSwingups in one pixel vector
environment (`gym.make_vec(..., vectorization_mode='vector_entry_point', pixels=True)`):
its frames per second, wall-clock (what parallel drawing buys), against N x the floor's
frame in the same run (N frames on one raw renderer), on the render threads (one per CPU)
and on one thread; the process CPU time per frame and the cores it kept busy (load from
other processes shows there: wall-clock figures need an idle machine); and a whole step
(physics and frames) per second.
"""

from __future__ import annotations

import copy
import importlib
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium
import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import tasks
from composer.pixels import frame
from mjcf.sim import rendering

SIZES = ((64, 64), (84, 84), (480, 640))
VECTOR_COUNTS = (1, 4, 16)
ROUNDS = 5
FRAMES = 20
FLOOR_XML = """
<mujoco>
  <visual><quality shadowsize="0"/></visual>
  <worldbody>
    <light pos="0 0 3"/>
    <geom type="plane" size="2 2 0.1"/>
    <body pos="0 0 0.5"><geom type="capsule" size="0.1 0.3"/></body>
  </worldbody>
</mujoco>
"""
_FLAG = mujoco.mjtRndFlag


def best_ms(draws: dict[str, Callable[[], Any]], rounds: int, frames: int) -> dict[str, float]:
    """Best per-frame milliseconds of process CPU time of each draw, rounds alternating."""
    for draw in draws.values():
        draw()  # first frames upload textures and meshes
    best = dict.fromkeys(draws, float("inf"))
    for _ in range(rounds):
        for label, draw in draws.items():
            start = time.process_time()
            for _ in range(frames):
                draw()
            best[label] = min(best[label], (time.process_time() - start) / frames * 1e3)
    return best


def raw_draw(
    model: mujoco.MjModel, data: mujoco.MjData, height: int, width: int, camera: int | str = -1,
    flags: dict[int, int] | None = None,
) -> tuple[Callable[[], np.ndarray], mujoco.Renderer]:  # fmt: skip
    """A raw mujoco.Renderer of `model` as it is, and a function drawing one frame."""
    renderer = mujoco.Renderer(model, height, width)

    def draw() -> np.ndarray:
        renderer.update_scene(data, camera=camera)
        for flag, value in (flags or {}).items():
            renderer.scene.flags[flag] = value
        return renderer.render()

    return draw, renderer


def floor_scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The floor's model and data."""
    model = mujoco.MjModel.from_xml_string(FLOOR_XML)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def settled(name: str, **kwargs: Any) -> gymnasium.Env:
    """The task made by gym.make, reset with seed 0 and stepped 10 times with zero action."""
    env = gymnasium.make(f"composer/{name}-v0", **kwargs)
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, env.action_space.dtype)
    for _ in range(10):
        env.step(zero)
    return env


def measure(name: str, height: int, width: int, rounds: int, frames: int) -> dict[str, float]:
    """Per-frame ms of the floor, ours and before at one size, frames per second and ratios."""
    env = settled(name, render_mode="rgb_array", width=width, height=height)
    inner = env.unwrapped
    model, data = inner.physics.model, inner.physics.data
    floor_model, floor_data = floor_scene()
    floor, floor_renderer = raw_draw(floor_model, floor_data, height, width)
    draws: dict[str, Callable[[], Any]] = {"floor": floor, "ours": env.render}
    before_renderer = None
    if height <= model.vis.global_.offheight and width <= model.vis.global_.offwidth:
        camera = getattr(inner.task, "render_camera", -1)
        draws["before"], before_renderer = raw_draw(model, data, height, width, camera)
    found = best_ms(draws, rounds, frames)
    for renderer in (floor_renderer, before_renderer):
        if renderer is not None:
            renderer.close()
    env.close()
    result = {f"{label}_ms": ms for label, ms in found.items()}
    result["fps"] = 1e3 / found["ours"]
    result["ours_vs_floor"] = found["ours"] / found["floor"]
    if "before" in found:
        result["before_vs_floor"] = found["before"] / found["floor"]
    return result


def factors(name: str, rounds: int, frames: int) -> dict[str, Any]:
    """What each render setting and part of the scene costs on top of our 64x64 frame of
    `name`, in floors, and the time to make a renderer (see the module docstring)."""
    size = 64
    env = settled(name)
    inner = env.unwrapped
    model, data = inner.physics.model, inner.physics.data
    camera = getattr(inner.task, "render_camera", -1)
    ours = rendering.frame_settings(size, size)
    defaults = {"quality.shadowsize": 4096, "quality.offsamples": 4,
                "global.offwidth": 640, "global.offheight": 480}  # fmt: skip
    msaa = {**ours, "quality.offsamples": 4}
    planes = model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE

    def variant(settings: dict[str, int], change: str = "") -> mujoco.MjModel:
        copied = copy.copy(model)
        for key, value in settings.items():
            section, attribute = key.split(".")
            target = copied.vis.quality if section == "quality" else copied.vis.global_
            setattr(target, attribute, value)
        if change == "textures":
            copied.mat_texid[:] = -1
        elif change == "lights":
            copied.light_active[:] = 0
        elif change == "grid":
            copied.geom_size[planes, 2] = 0.1
        return copied

    # label: (model, scene flags); costs are differences between two of them.
    scenes: dict[str, tuple[mujoco.MjModel, dict[int, int]]] = {
        "defaults": (variant(defaults), {}),
        "ours": (variant(ours), {}),
        "ours + shadow map 4096": (variant({**ours, "quality.shadowsize": 4096}), {}),
        "ours + 4x multisampling": (variant(msaa), {}),
        "ours + 4x multisampling + 640x480 buffer": (
            variant({**msaa, "global.offwidth": 640, "global.offheight": 480}), {},
        ),
        "ours + plane grid 10 cm": (variant(ours, "grid"), {}),
        "ours - reflections": (variant(ours), {_FLAG.mjRND_REFLECTION: 0}),
        "ours - skybox": (variant(ours), {_FLAG.mjRND_SKYBOX: 0}),
        "ours - textures": (variant(ours, "textures"), {}),
        "ours - lights but the headlight": (variant(ours, "lights"), {}),
    }  # fmt: skip
    floor_model, floor_data = floor_scene()
    draw, renderer = raw_draw(floor_model, floor_data, size, size)
    draws, renderers = {"floor": draw}, [renderer]
    for label, (scene_model, flags) in scenes.items():
        draws[label], renderer = raw_draw(scene_model, data, size, size, camera, flags)
        renderers.append(renderer)
    found = best_ms(draws, rounds, frames)
    for renderer in renderers:
        renderer.close()
    floor = found["floor"]
    ours_ms = found["ours"]
    costs = {
        "shadow map 4096": found["ours + shadow map 4096"] - ours_ms,
        "4x multisampling": found["ours + 4x multisampling"] - ours_ms,
        "640x480 buffer (with multisampling)": found["ours + 4x multisampling + 640x480 buffer"]
        - found["ours + 4x multisampling"],
        "plane grid 10 cm": found["ours + plane grid 10 cm"] - ours_ms,
        "reflections": ours_ms - found["ours - reflections"],
        "skybox": ours_ms - found["ours - skybox"],
        "textures": ours_ms - found["ours - textures"],
        "lights but the headlight": ours_ms - found["ours - lights but the headlight"],
    }
    env.close()
    return {
        "floor_ms": floor, "defaults_vs_floor": found["defaults"] / floor,
        "ours_vs_floor": ours_ms / floor,
        "cost_floors": {label: ms / floor for label, ms in costs.items()},
        "make_renderer_ms": making_renderer(variant(ours), size, max(1, rounds // 2)),
    }  # fmt: skip


def making_renderer(model: mujoco.MjModel, size: int, rounds: int) -> dict[str, float]:
    """Best ms of process CPU time to make MuJoCo's render context in a new OpenGL context
    (the context included: what every renderer cost) and in one that made one before (what
    a renderer costs when `mjcf.sim.rendering` hands it a kept context)."""
    base = importlib.import_module(f"mujoco.{rendering.backend()}").GLContext
    fresh = reused = float("inf")
    for _ in range(rounds):
        start = time.process_time()
        gl = base(size, size)
        gl.make_current()
        first = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        fresh = min(fresh, (time.process_time() - start) * 1e3)
        start = time.process_time()
        second = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        reused = min(reused, (time.process_time() - start) * 1e3)
        second.free()
        first.free()
        gl.free()
    return {"new_gl_context": fresh, "kept_gl_context": reused}


def best_wall_ms(
    draws: dict[str, Callable[[], Any]], rounds: int, calls: int
) -> dict[str, tuple[float, float]]:
    """Per call of each draw, rounds alternating: the best wall-clock milliseconds, and
    the process CPU milliseconds of that round."""
    for draw in draws.values():
        draw()
    best = dict.fromkeys(draws, (float("inf"), 0.0))
    for _ in range(rounds):
        for label, draw in draws.items():
            start, cpu = time.perf_counter(), time.process_time()
            for _ in range(calls):
                draw()
            wall = (time.perf_counter() - start) / calls * 1e3
            if wall < best[label][0]:
                best[label] = (wall, (time.process_time() - cpu) / calls * 1e3)
    return best


def vector_frames(name: str, n: int, nthread: int) -> tuple[Any, Callable[[], Any]]:
    """A settled pixel vector environment of n `name`s at 64x64, and a function drawing
    every environment's frame as its step does."""
    venv = gymnasium.make_vec(
        f"composer/{name}-v0", num_envs=n, vectorization_mode="vector_entry_point",
        pixels=True, width=64, height=64, nthread=nthread,
    )  # fmt: skip
    venv.reset(seed=0)
    zero = np.zeros(venv.action_space.shape, venv.action_space.dtype)
    for _ in range(10):
        venv.step(zero)
    envs, ids = venv.environments, range(n)
    camera = getattr(envs[0].task, "render_camera", -1)

    def draw() -> list[np.ndarray]:
        return venv.draw(ids, lambda i: frame(envs[i].physics, (64, 64), camera))

    return venv, draw


def vector(name: str, rounds: int, calls: int) -> dict[str, Any]:
    """Frames per second of N pixel environments at 64x64 against N x the floor (see the
    module docstring)."""
    threads = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1
    floor_model, floor_data = floor_scene()
    floor, floor_renderer = raw_draw(floor_model, floor_data, 64, 64)
    results: dict[str, Any] = {"threads": threads}
    for n in VECTOR_COUNTS:
        venv, draw = vector_frames(name, n, threads)
        serial_venv, serial_draw = vector_frames(name, n, 1)
        zero = np.zeros(venv.action_space.shape, venv.action_space.dtype)
        timed = best_wall_ms(
            {"floor": floor, "threads": draw, "one thread": serial_draw,
             "step": lambda venv=venv, zero=zero: venv.step(zero)},
            rounds, max(1, calls // n),
        )  # fmt: skip
        venv.close()
        serial_venv.close()
        found = {label: wall for label, (wall, _) in timed.items()}
        floors = n * found["floor"]
        results[f"n{n}"] = {
            "floor_ms": found["floor"],
            "fps": 1e3 * n / found["threads"],
            "one_thread_fps": 1e3 * n / found["one thread"],
            "floor_fps": 1e3 / found["floor"],
            "vector_vs_n_floors": found["threads"] / floors,
            "one_thread_vs_n_floors": found["one thread"] / floors,
            "threads_vs_one_thread": found["threads"] / found["one thread"],
            "cores_used": timed["threads"][1] / found["threads"],
            "cpu_ms_per_frame": timed["threads"][1] / n,
            "one_thread_cpu_ms_per_frame": timed["one thread"][1] / n,
            "step_fps": 1e3 * n / found["step"],
        }
    floor_renderer.close()
    return results


def main(*names: str, quick: bool = False) -> dict[str, Any]:
    """Measure and print the tasks `names` (all registered ones by default)."""
    names = names or tuple(env_id.split("/")[1].rsplit("-", 1)[0] for env_id in tasks.IDS)
    rounds, frames = (1, 2) if quick else (ROUNDS, FRAMES)
    print(f"backend {rendering.backend()}; ms of process CPU time per frame, best of {rounds}")
    results: dict[str, Any] = {}
    for name in names:
        results[name] = {}
        for height, width in SIZES:
            heavy = name == "ArmPushBox" or height * width > 100_000
            found = measure(name, height, width, rounds, max(1, frames // 4) if heavy else frames)
            results[name][f"{height}x{width}"] = found
            before = found.get("before_vs_floor")
            print(
                f"{name:16} {height:3}x{width:<3} ours {found['ours_ms']:7.2f} ms "
                f"({found['fps']:6.0f} fps) = {found['ours_vs_floor']:5.1f} x floor "
                f"({found['floor_ms']:.2f} ms)"
                + (f"; before {before:6.1f} x floor" if before is not None else "")
            )
    name = "CartpoleSwingup" if "CartpoleSwingup" in names else names[0]
    found = factors(name, rounds, frames)
    results["factors"] = {name: found}
    print(
        f"\n{name} at 64x64 (floor {found['floor_ms']:.2f} ms): MuJoCo's default settings "
        f"{found['defaults_vs_floor']:.1f} x floor, ours {found['ours_vs_floor']:.1f} x floor; "
        "each alone on top of ours costs (floors):"
    )
    for label, cost in found["cost_floors"].items():
        print(f"  {label:36} {cost:6.2f}")
    making = found["make_renderer_ms"]
    print(
        f"  making a renderer's contexts: {making['new_gl_context']:.0f} ms in a new OpenGL "
        f"context, {making['kept_gl_context']:.0f} ms in one kept from a closed renderer"
    )
    results["vector"] = {name: print_vector(name, rounds, frames * 4)}
    return results


def print_vector(name: str, rounds: int, calls: int) -> dict[str, Any]:
    """Measure and print `vector`'s figure of task `name`."""
    found = vector(name, rounds, calls)
    print(
        f"\n{name} pixel vector environment, 64x64, {found['threads']} render threads; "
        "wall-clock, N x floor = N frames on one raw renderer of the floor:"
    )
    for n in VECTOR_COUNTS:
        row = found[f"n{n}"]
        print(
            f"  N={n:<3} {row['fps']:6.0f} frames/s ({row['vector_vs_n_floors']:.2f} x N floors;"
            f" one thread {row['one_thread_fps']:6.0f}/s, {row['one_thread_vs_n_floors']:.2f});"
            f" floor {row['floor_fps']:5.0f}/s; steps with frames {row['step_fps']:6.0f}/s;"
            f" CPU per frame {row['cpu_ms_per_frame']:.2f} ms on {row['cores_used']:.1f} cores"
            f" ({row['one_thread_cpu_ms_per_frame']:.2f} ms on one thread)"
        )
    return found


if __name__ == "__main__":
    if sys.argv[1:2] == ["vector"]:
        print_vector("CartpoleSwingup", ROUNDS, FRAMES * 4)
    else:
        main(*sys.argv[1:])
