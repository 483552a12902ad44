"""Reading and writing MJCF with mjcf, next to MuJoCo's and lxml's own, same run.

    python bench/bench_parse.py

For each model: `mjcf.from_path` against `mujoco.MjSpec.from_file` and a bare
`lxml.etree.parse` of the same file; `to_xml_string()` against lxml's `tostring` of
the parsed file; and writing + compiling (`mjcf.Physics.from_mjcf_model`'s work)
against `mujoco.MjModel.from_xml_string` of the same text. Each figure is the best of
alternating rounds, so that noise from other processes hits both sides alike.
Targets: parse within 2x of MjSpec, write within 5x of lxml, write + compile within
1.3x of MuJoCo's compile.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))  # run from a checkout

import gymnasium  # noqa: E402
import mujoco  # noqa: E402
from lxml import etree  # noqa: E402

import mjcf  # noqa: E402
from mjcf import compiler  # noqa: E402

GYM = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MENAGERIE = REPO.parent / "shared" / "models" / "menagerie"


def best_of(functions: list[Callable[[], object]], seconds: float = 1.0) -> list[float]:
    """Best time per call of each function, timed in alternating rounds for `seconds`."""
    best = [float("inf")] * len(functions)
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline:
        for i, function in enumerate(functions):
            start = time.perf_counter()
            function()
            best[i] = min(best[i], time.perf_counter() - start)
    return best


def models() -> dict[str, Path]:
    """The models measured: gymnasium's and, when present, the menagerie robots."""
    found = {"humanoid": GYM / "humanoid.xml", "ant": GYM / "ant.xml"}
    for name, relative in (
        ("ur5e", "universal_robots_ur5e/ur5e.xml"),
        ("2f85", "robotiq_2f85/2f85.xml"),
    ):
        if (MENAGERIE / relative).exists():
            found[name] = MENAGERIE / relative
    return found


def main() -> dict[str, dict[str, float]]:
    """Measure every model; print a table and return the ratios."""
    os.chdir(os.path.dirname(os.path.abspath(__file__)))
    results: dict[str, dict[str, float]] = {}
    print(f"{'model':10} {'parse ms':>9} {'MjSpec':>8} {'ratio':>6} {'lxml':>7} | "
          f"{'write ms':>9} {'lxml':>7} {'ratio':>6} | {'write+compile':>13} {'MuJoCo':>8} {'ratio':>6}")  # fmt: skip
    for name, path in models().items():
        text = str(path)
        tree = etree.parse(text)
        root = mjcf.from_path(path)
        xml = root.to_xml_string()
        assets = root.get_assets()
        ours, spec, lxml_parse = best_of(
            [
                lambda: mjcf.from_path(path),
                lambda: mujoco.MjSpec.from_file(text),
                lambda: etree.parse(text),
            ]
        )
        write, lxml_write = best_of([root.to_xml_string, lambda: etree.tostring(tree)])
        both, mujoco_compile = best_of(
            [lambda: compiler.compile_composition(root),
             lambda: mujoco.MjModel.from_xml_string(xml, assets)],
            seconds=2.0,
        )  # fmt: skip
        results[name] = {
            "parse_vs_mjspec": ours / spec,
            "parse_vs_lxml": ours / lxml_parse,
            "write_vs_lxml": write / lxml_write,
            "write_compile_vs_mujoco": both / mujoco_compile,
        }
        print(f"{name:10} {ours * 1e3:9.3f} {spec * 1e3:8.3f} {ours / spec:6.2f} {lxml_parse * 1e3:7.3f} | "
              f"{write * 1e3:9.3f} {lxml_write * 1e3:7.3f} {write / lxml_write:6.2f} | "
              f"{both * 1e3:13.3f} {mujoco_compile * 1e3:8.3f} {both / mujoco_compile:6.2f}")  # fmt: skip
    return results


if __name__ == "__main__":
    main()
