"""`composer show TASK`: the task's scene, observations and actions; with `--out FILE.png`
also a rendered frame (without it nothing is written).

    $ composer show Reach --out reach.png
    Reach (composer/Reach-v0): Move a planar 2-link arm's fingertip to a random target
    timesteps: physics 0.005 s, control 0.04 s (8 substeps); time limit 3 s (75 steps)
    entities ...                           (each one's bodies, joints and actuators)
    observations (10 values) ...           (each one's name, shape and dtype)
    actions (2 values): Box(-1.0, 1.0, (2,), float32)
    frame: reach.png (320x240)
"""

from __future__ import annotations

import argparse
import math
import textwrap
from collections.abc import Iterator

import gymnasium
import mujoco
import numpy as np
from gymnasium.spaces import flatdim

from composer.cli import catalog, output, rollout, video
from composer.entity import Entity
from composer.environment import Environment
from composer.pixels import PixelEnvironment

NO_BREAK = "\N{NO-BREAK SPACE}"


def run(args: argparse.Namespace) -> int:
    """Print the scene and write the frame; returns the exit status."""
    info = args.info
    path = output.file(video.png_target(args.out)) if args.out else None
    env = catalog.make(info, flatten=False, render_mode="rgb_array" if path else None)
    try:
        env.reset(seed=args.seed)
        print(f"{info.name} ({info.env_id}): {info.description}")
        print(f"timesteps: {_timesteps(env, info.default_kwargs.get('time_limit'))}")
        print("entities")
        for line in scene_lines(env):
            print(f"  {line}")
        observations = env.observation_space
        assert isinstance(observations, gymnasium.spaces.Dict), "made with flatten=False"
        print(f"observations ({_values(flatdim(observations))})")
        width = max(map(len, observations), default=0)
        for name, space in observations.items():
            print(f"  {name:<{width}}  {space.shape}  {space.dtype}")
        print(f"actions ({_values(flatdim(env.action_space))}): {env.action_space}")
        frame = rollout.render_frame(env) if path else None
    finally:
        env.close()
    if path is None or frame is None:
        print("frame: none (--out FILE.png renders one)")
        return 0
    video.write_png(frame, path)
    print(f"frame: {path} ({frame.shape[1]}x{frame.shape[0]})")
    return 0


def _values(count: int) -> str:
    return f"{count} value{'s' if count != 1 else ''}"


def _timesteps(env: Environment | PixelEnvironment, time_limit: float | None) -> str:
    task = env.task
    text = (
        f"physics {task.physics_timestep:g} s, control {task.control_timestep:g} s "
        f"({task.physics_steps_per_control_step} substeps)"
    )
    if time_limit is None:
        return f"{text}; no time limit"
    steps = math.ceil(time_limit / task.control_timestep - 1e-9)
    return f"{text}; time limit {time_limit:g} s ({steps} steps)"


def scene_lines(env: Environment | PixelEnvironment) -> Iterator[str]:
    """Lines describing each entity and the bodies, joints and actuators it owns, read from
    the compiled model and grouped under the entity whose name scope they carry ('arm/...');
    the root entity owns the unscoped ones:

        floor (Floor)
          bodies     world, target
          arm (PlanarArm)
            bodies     arm/upper, arm/lower
            joints     arm/shoulder hinge, arm/elbow hinge [-2.8, 2.8]
            actuators  arm/shoulder -> arm/shoulder, arm/elbow -> arm/elbow
    """
    root = env.task.root_entity
    scopes = {entity: entity.scope_in(root) for entity in root.iter_entities()}
    owned: dict[Entity, dict[str, list[str]]] = {e: {} for e in scopes}
    for kind, label in _elements(env.physics.model):
        owner = _owner(label.partition(" ")[0], scopes)
        owned[owner].setdefault(kind, []).append(label)
    for entity, scope in scopes.items():
        depth = scope.count("/") + (scope != "")
        indent = "  " * depth
        yield f"{indent}{entity.name} ({type(entity).__name__})"
        for kind in ("bodies", "joints", "actuators"):
            if kind in owned[entity]:
                # Lines break between elements only: spaces inside a label are no-break.
                labels = ", ".join(label.replace(" ", NO_BREAK) for label in owned[entity][kind])
                lines = textwrap.wrap(
                    labels, width=96, break_on_hyphens=False, break_long_words=False,
                    initial_indent=f"{indent}  {kind:<10} ", subsequent_indent=indent + " " * 13,
                )  # fmt: skip
                yield from (line.replace(NO_BREAK, " ") for line in lines)


def _owner(name: str, scopes: dict[Entity, str]) -> Entity:
    """The entity with the longest scope `name` starts with (the root for unscoped names)."""
    best, best_length = next(iter(scopes)), -1
    for entity, scope in scopes.items():
        if (scope == "" or name.startswith(scope + "/")) and len(scope) > best_length:
            best, best_length = entity, len(scope)
    return best


def _elements(model: mujoco.MjModel) -> Iterator[tuple[str, str]]:
    """('bodies' | 'joints' | 'actuators', label) for every named or numbered element."""
    obj = mujoco.mjtObj
    for i in range(model.nbody):
        yield "bodies", _name(model, obj.mjOBJ_BODY, i, "body")
    for i in range(model.njnt):
        kind = mujoco.mjtJoint(model.jnt_type[i]).name.removeprefix("mjJNT_").lower()
        label = f"{_name(model, obj.mjOBJ_JOINT, i, 'joint')} {kind}"
        if model.jnt_limited[i]:
            label += f" {_range(model.jnt_range[i])}"
        yield "joints", label
    for i in range(model.nu):
        label = _name(model, obj.mjOBJ_ACTUATOR, i, "actuator")
        if model.actuator_trntype[i] == mujoco.mjtTrn.mjTRN_JOINT:
            label += f" -> {_name(model, obj.mjOBJ_JOINT, model.actuator_trnid[i, 0], 'joint')}"
        if model.actuator_ctrllimited[i]:
            label += f" ctrl {_range(model.actuator_ctrlrange[i])}"
        yield "actuators", label


def _name(model: mujoco.MjModel, kind: mujoco.mjtObj, index: int, noun: str) -> str:
    return mujoco.mj_id2name(model, kind, int(index)) or f"<{noun} {index}>"


def _range(values: np.ndarray) -> str:
    return f"[{values[0]:g}, {values[1]:g}]"
