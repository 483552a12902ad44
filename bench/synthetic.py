"""Synthetic MJCF models for the benchmarks, written as text MuJoCo compiles.

    creature_xml(CMU_HUMANOID)     # a humanoid of the size and kind of dm_control's CMU one
    creature_xml(RODENT)           # deeper, with many more default classes and sensors
    chains_xml(chains=500, links=200)   # 100,000 bodies

dm_control's rodent and CMU humanoid files cannot ship with this repository; these models
have what makes them slow to read: depth (a spine, a tail and limbs of many segments),
many nested default classes that the elements use, and many sensors, actuators, tendons
and contact exclusions naming the bodies and joints.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple


class Creature(NamedTuple):
    """The shape of a synthetic creature."""

    name: str
    spine: int  # bodies from the pelvis to the head
    tail: int  # bodies of the tail (0: none)
    limbs: int  # limbs, each on a spine body
    segments: int  # bodies per limb
    joints_per_body: int  # hinges per limb body (1 to 3)
    class_groups: int  # default classes: this many groups of nested classes
    joint_sensors: int  # joints (from the first) with a position and a velocity sensor


# About dm_control's CMU humanoid (31 bodies, 56 hinges, 56 motors) and rodent (about
# 60 bodies, 100 hinges, tens of nested classes and a hundred sensors), by shape.
CMU_HUMANOID = Creature("cmu_like", spine=7, tail=0, limbs=4, segments=6, joints_per_body=2,
                        class_groups=4, joint_sensors=0)  # fmt: skip
RODENT = Creature("rodent_like", spine=9, tail=14, limbs=4, segments=8, joints_per_body=2,
                  class_groups=12, joint_sensors=30)  # fmt: skip

_AXES = ("1 0 0", "0 1 0", "0 0 1")


def creature_xml(shape: Creature) -> str:
    """The MJCF text of a creature of `shape`."""
    out = [
        f'<mujoco model="{shape.name}">',
        '  <compiler angle="degree" autolimits="true"/>',
        '  <option timestep="0.002"/>',
        "  <default>",
        '    <joint damping="0.5" armature="0.01" range="-60 60"/>',
        '    <geom type="capsule" size="0.02" friction="0.7" rgba="0.8 0.6 0.4 1"/>',
        '    <motor ctrlrange="-1 1" gear="10"/>',
        '    <site size="0.01" group="3"/>',
    ]
    classes = []
    for group in range(shape.class_groups):
        out.append(f'    <default class="group{group}">')
        out.append(f'      <joint stiffness="{group % 5 + 1}" damping="{0.2 * group + 0.5}"/>')
        out.append(f'      <geom density="{900 + 10 * group}"/>')
        for level in ("stiff", "soft"):
            name = f"group{group}_{level}"
            classes.append(name)
            out.append(f'      <default class="{name}">')
            out.append(f'        <joint range="-{30 + group} {40 + group}"/>')
            out.append(f'        <motor gear="{5 + group}"/>')
            out.append(f'        <default class="{name}_touch">')
            out.append('          <site type="box" rgba="0 0 1 0.3"/>')
            out.append("        </default>")
            out.append("      </default>")
        out.append("    </default>")
    out.append("  </default>")
    out.append("  <worldbody>")
    out.append('    <geom name="floor" type="plane" size="10 10 0.1" conaffinity="1"/>')
    out.append('    <light name="sun" pos="0 0 5" dir="0 0 -1"/>')
    joints: list[str] = []
    bodies: list[str] = []
    touch: list[str] = []
    counter = [0]

    def klass() -> str:
        counter[0] += 1
        return classes[counter[0] % len(classes)]

    def body(name: str, depth: int, joint_count: int, pos: str) -> str:
        indent = "  " * depth
        bodies.append(name)
        cls = klass()
        lines = [f'{indent}<body name="{name}" pos="{pos}" childclass="{cls}">']
        for j in range(joint_count):
            joint = f"{name}_j{j}"
            joints.append(joint)
            low, high = -30 - 5 * j - len(joints) % 7, 45 + 10 * j + len(joints) % 5
            lines.append(
                f'{indent}  <joint name="{joint}" axis="{_AXES[j % 3]}" range="{low} {high}"/>'
            )
        k = len(bodies)
        lines.append(
            f'{indent}  <geom name="{name}_geom" size="0.0{2 + k % 5} 0.0{4 + k % 4}" '
            f'pos="0 0.00{k % 9} 0.04" quat="0.{7 + k % 3} 0 0.0{k % 8} 0.1"/>'
        )
        site = f"{name}_touch"
        touch.append(site)
        lines.append(f'{indent}  <site name="{site}" class="{cls}_touch" size="0.02 0.02 0.01"/>')
        out.extend(lines)
        return indent

    out.append('    <body name="pelvis" pos="0 0 0.5">')
    out.append('      <freejoint name="root"/>')
    out.append('      <geom name="pelvis_geom" type="sphere" size="0.05"/>')
    out.append('      <site name="imu" pos="0 0 0"/>')
    bodies.append("pelvis")
    closing: list[str] = []
    pairs = shape.limbs // 2
    limb_at = {round((i + 1) * shape.spine / (pairs + 1)) for i in range(pairs)}
    for s in range(shape.spine):
        closing.append(body(f"spine{s}", 3 + s, 3 if s % 2 else 2, "0 0 0.08"))
        if s in limb_at:
            for side in ("left", "right"):
                limb = f"{side}{s}"
                inner = []
                for g in range(shape.segments):
                    depth = 4 + s + g
                    x = "0.06 0 0" if side == "left" else "-0.06 0 0"
                    inner.append(body(f"{limb}_seg{g}", depth, shape.joints_per_body, x))
                for indent in reversed(inner):
                    out.append(f"{indent}</body>")
    for indent in reversed(closing):
        out.append(f"{indent}</body>")
    if shape.tail:
        inner = [body(f"tail{t}", 3 + t, 2, "0 -0.05 0") for t in range(shape.tail)]
        for indent in reversed(inner):
            out.append(f"{indent}</body>")
    out.append("    </body>")
    out.append("  </worldbody>")
    out.append("  <contact>")
    for a, b in itertools.pairwise(bodies):
        out.append(f'    <exclude body1="{a}" body2="{b}"/>')
    out.append("  </contact>")
    out.append("  <tendon>")
    for i in range(0, len(joints) - 1, 4):
        out.append(f'    <fixed name="coupling{i}">')
        out.append(f'      <joint joint="{joints[i]}" coef="1"/>')
        out.append(f'      <joint joint="{joints[i + 1]}" coef="-0.5"/>')
        out.append("    </fixed>")
    out.append("  </tendon>")
    out.append("  <actuator>")
    for i, joint in enumerate(joints):
        out.append(
            f'    <motor name="{joint}" joint="{joint}" class="{classes[i % len(classes)]}"/>'
        )
    out.append("  </actuator>")
    out.append("  <sensor>")
    for kind in ("accelerometer", "velocimeter", "gyro"):
        out.append(f'    <{kind} name="{kind}" site="imu"/>')
    for joint in joints[: shape.joint_sensors]:
        out.append(f'    <jointpos name="{joint}_pos" joint="{joint}"/>')
        out.append(f'    <jointvel name="{joint}_vel" joint="{joint}"/>')
    for site in touch[::4]:
        out.append(f'    <touch name="{site}" site="{site}"/>')
    for name in bodies[::6]:
        out.append(f'    <framepos name="{name}_pos" objtype="body" objname="{name}"/>')
    out.append("  </sensor>")
    out.append("</mujoco>")
    return "\n".join(out) + "\n"


def chains_xml(chains: int, links: int) -> str:
    """`chains` chains of `links` nested bodies, each with a hinge and a capsule, side by
    side in the world body: `chains * links` bodies, nested `links` deep."""
    parts = ['<mujoco model="chains">\n  <worldbody>\n']
    for c in range(chains):
        for link in range(links):
            indent = "  " * (link + 2)
            parts.append(
                f'{indent}<body name="c{c}_b{link}" pos="0 0 0.1">\n'
                f'{indent}  <joint name="c{c}_j{link}" type="hinge" axis="0 1 0"/>\n'
                f'{indent}  <geom type="capsule" size="0.02" fromto="0 0 0 0 0 0.1"/>\n'
            )
        parts.extend("  " * (link + 2) + "</body>\n" for link in reversed(range(links)))
    parts.append("  </worldbody>\n</mujoco>\n")
    return "".join(parts)
