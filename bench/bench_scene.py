"""Whole scenes: memory of the Python tree against the compiled MjModel, and writing +
compiling against MuJoCo's own compile of the same text, same run.

    python bench/bench_scene.py              # 100 synthetic robots, gymnasium's models, UR5e

Memory: a synthetic robot (a free torso, four two-joint legs, eight motors, eight joint
sensors, no assets) is built 100 times with mjcf and attached to an arena; tracemalloc
counts the Python memory the tree holds, before and after compiling it (mjcf keeps its
compile caches), against `mujoco.mj_sizeModel` of the compiled model. Target: < 10x.

Compile, per scene (humanoid, ant, UR5e + 2F-85, one and 100 synthetic robots in an arena):
  write+compile  `to_xml_string()` then `mujoco.MjModel.from_xml_string` of that text
  physics        `mjcf.Physics.from_mjcf_model` (what composer.Environment calls) on the
                 tree unchanged since the last compile, as when recompiling the same model
  changed        the same after one attribute of the scene changed (as composer recompiles
                 after `initialize_episode_mjcf` changes the model)
  cold           the same on a tree just built or parsed, never written before
  mujoco         `mujoco.MjModel.from_xml_string` of the same text (the floor): the text
                 `to_xml_string()` writes for write+compile; for physics, the text
                 `from_mjcf_model` compiles, which names files on disk by path (MuJoCo
                 then reads them itself, and reuses the meshes it has processed before)
  +step          `from_mjcf_model` and one `physics.step()`, against `from_xml_string`,
                 `MjData` and one `mj_step`: a physics makes its MjData when first used,
                 which costs mujoco's bindings about 0.3 ms whatever the model
each the best of alternating rounds, in the process' CPU time (`time.process_time`:
time other processes take is not counted; mjcf's writer reuses its attribute text while the
tree is unchanged); `write cold` is `to_xml_string()` once on a freshly built tree.
Targets: write+compile within 1.3x of mujoco, physics within 1.1x.
"""

from __future__ import annotations

import gc
import sys
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import gymnasium
import mujoco

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import mjcf
from mjcf.io import serializer

REPO = Path(__file__).resolve().parents[1]
clock = time.process_time
GYM = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MENAGERIE = REPO / "entities" / "menagerie"  # shipped with the package
UR5E = MENAGERIE / "universal_robots_ur5e" / "ur5e.xml"
ROBOTIQ = MENAGERIE / "robotiq_2f85" / "2f85.xml"


def robot(name: str) -> mjcf.RootElement:
    """A synthetic quadruped: torso, four legs of two hinges, motors and joint sensors."""
    root = mjcf.RootElement(model=name)
    torso = root.worldbody.add("body", name="torso")
    torso.add("geom", name="torso", type="sphere", size=[0.25])
    for k, (x, y) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
        hip = torso.add("body", name=f"hip_{k}", pos=[0.2 * x, 0.2 * y, 0])
        hip.add("joint", name=f"hip_{k}", type="hinge", axis=[0, 0, 1], range=[-30, 30])
        hip.add("geom", type="capsule", fromto=[0, 0, 0, 0.2 * x, 0.2 * y, 0], size=[0.08])
        foot = hip.add("body", name=f"ankle_{k}", pos=[0.2 * x, 0.2 * y, 0])
        foot.add("joint", name=f"ankle_{k}", type="hinge", axis=[-y, x, 0], range=[30, 70])
        foot.add("geom", type="capsule", fromto=[0, 0, 0, 0.4 * x, 0.4 * y, 0], size=[0.08])
        for joint in (f"hip_{k}", f"ankle_{k}"):
            root.actuator.add("motor", name=joint, joint=joint, gear=[150], ctrlrange=[-1, 1])
            root.sensor.add("jointpos", name=joint, joint=joint)
    return root


def arena(count: int) -> mjcf.RootElement:
    """`count` synthetic robots on a 10-wide grid, each on a free joint."""
    root = mjcf.RootElement(model="arena")
    root.compiler.angle = "degree"
    root.worldbody.add("geom", name="floor", type="plane", size=[50, 50, 0.1])
    for i in range(count):
        frame = root.worldbody.attach(robot(f"robot{i}"))
        frame.pos = [2.0 * (i % 10), 2.0 * (i // 10), 0.75]
        frame.add("freejoint")
    return root


def memory(count: int) -> dict[str, float]:
    """Python bytes of the tree (and with its compile caches) against the MjModel's."""
    arena(2)  # imports and schema tables, not the tree's
    gc.collect()
    tracemalloc.start()
    root = arena(count)
    gc.collect()
    tree = tracemalloc.get_traced_memory()[0]
    model = mjcf.Physics.from_mjcf_model(root).model
    gc.collect()
    compiled = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    size = mujoco.mj_sizeModel(model)
    return {
        "robots": count, "tree_mb": tree / 1e6, "tree_after_compile_mb": compiled / 1e6,
        "mjmodel_mb": size / 1e6, "tree_vs_mjmodel": tree / size,
        "tree_after_compile_vs_mjmodel": compiled / size,
    }  # fmt: skip


def scenes(count: int) -> dict[str, Callable[[], mjcf.RootElement]]:
    """Builders of the scenes measured."""
    found = {
        "humanoid": lambda: mjcf.from_path(GYM / "humanoid.xml"),
        "ant": lambda: mjcf.from_path(GYM / "ant.xml"),
        "1 robot": lambda: arena(1),
        f"{count} robots": lambda: arena(count),
    }

    def arm() -> mjcf.RootElement:
        root = mjcf.from_path(UR5E)
        root.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
        return root

    found["ur5e+2f85"] = arm
    return found


def compile_times(build: Callable[[], mjcf.RootElement], rounds: int) -> dict[str, float]:
    """Best seconds of each way to compile the scene `build` makes."""
    start = clock()
    root = build().root
    built = clock() - start
    light = root.worldbody.add("light", name="bench_light", pos=[0, 0, 3])
    start = clock()
    xml = root.to_xml_string()
    cold = clock() - start
    assets = root.get_assets()
    compiled_xml, compiled_assets = serializer.serialize_for_compile(root)[:2]
    best = dict.fromkeys(
        ("write_compile", "mujoco_written", "physics", "physics_changed", "physics_cold",
         "mujoco", "physics_step", "mujoco_step"),
        float("inf"),
    )  # fmt: skip
    best["write_cold"] = best["write"] = cold
    for round_index in range(rounds):
        fresh = build().root
        start = clock()
        mjcf.Physics.from_mjcf_model(fresh)
        best["physics_cold"] = min(best["physics_cold"], clock() - start)
        start = clock()
        text = root.to_xml_string()
        written = clock()
        mujoco.MjModel.from_xml_string(text, assets)
        done = clock()
        best["write"] = min(best["write"], written - start)
        best["write_compile"] = min(best["write_compile"], done - start)
        start = clock()
        mjcf.Physics.from_mjcf_model(root)
        best["physics"] = min(best["physics"], clock() - start)
        light.pos = [0, 0, 3 + 0.1 * (round_index + 1)]  # a change: its version moves on
        start = clock()
        mjcf.Physics.from_mjcf_model(root)
        best["physics_changed"] = min(best["physics_changed"], clock() - start)
        start = clock()
        mujoco.MjModel.from_xml_string(xml, assets)
        best["mujoco_written"] = min(best["mujoco_written"], clock() - start)
        start = clock()
        mujoco.MjModel.from_xml_string(compiled_xml, compiled_assets)
        best["mujoco"] = min(best["mujoco"], clock() - start)
        start = clock()
        mjcf.Physics.from_mjcf_model(root).step()
        best["physics_step"] = min(best["physics_step"], clock() - start)
        start = clock()
        model = mujoco.MjModel.from_xml_string(compiled_xml, compiled_assets)
        mujoco.mj_step(model, mujoco.MjData(model))
        best["mujoco_step"] = min(best["mujoco_step"], clock() - start)
    best["build"] = built
    return best


def main(count: int = 100, quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure and print; returns the figures and ratios by scene. `quick`: 5 robots,
    that scene only."""
    if quick:
        count = 5
    results: dict[str, dict[str, float]] = {"memory": memory(count)}
    m = results["memory"]
    print(f"{count} synthetic robots: Python tree {m['tree_mb']:.2f} MB "
          f"({m['tree_after_compile_mb']:.2f} MB with compile caches), MjModel "
          f"{m['mjmodel_mb']:.2f} MB: {m['tree_vs_mjmodel']:.2f}x "
          f"({m['tree_after_compile_vs_mjmodel']:.2f}x) (target < 10x)")  # fmt: skip
    print(f"{'scene':12} {'write ms':>9} {'cold':>8} {'MuJoCo ms':>10} {'write+compile':>14} "
          f"{'physics':>8} {'changed':>8} {'cold':>6} {'+step':>6}   (to MuJoCo)")  # fmt: skip
    for name, build in scenes(count).items():
        if quick and "robots" not in name:
            continue
        t = compile_times(build, 1 if quick else (5 if "100" in name else 40))
        t["write_compile_vs_mujoco"] = t["write_compile"] / t["mujoco_written"]
        t["physics_vs_mujoco"] = t["physics"] / t["mujoco"]
        t["physics_changed_vs_mujoco"] = t["physics_changed"] / t["mujoco"]
        t["physics_cold_vs_mujoco"] = t["physics_cold"] / t["mujoco"]
        t["physics_step_vs_mujoco_step"] = t["physics_step"] / t["mujoco_step"]
        results[name] = t
        print(f"{name:12} {t['write'] * 1e3:9.2f} {t['write_cold'] * 1e3:8.2f} "
              f"{t['mujoco'] * 1e3:10.2f} {t['write_compile_vs_mujoco']:14.2f} "
              f"{t['physics_vs_mujoco']:8.2f} {t['physics_changed_vs_mujoco']:8.2f} "
              f"{t['physics_cold_vs_mujoco']:6.2f} "
              f"{t['physics_step_vs_mujoco_step']:6.2f}")  # fmt: skip
    return results


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100)
