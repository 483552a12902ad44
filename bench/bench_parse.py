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
    robots = {"ur5e": "universal_robots_ur5e/ur5e.xml", "2f85": "robotiq_2f85/2f85.xml"}
    for name, relative in robots.items():
        if (MENAGERIE / relative).exists():
            found[name] = MENAGERIE / relative
    return found


def measure(path: Path, seconds: float = 1.0) -> dict[str, float]:
    """Seconds per call of each operation on one model, ours and the references, each
    timed for about `seconds` (compiling for twice that)."""
    text = str(path)
    tree = etree.parse(text)
    root = mjcf.from_path(path)
    xml = root.to_xml_string()
    assets = root.get_assets()
    parse, spec, lxml_parse = best_of(
        [lambda: mjcf.from_path(path), lambda: mujoco.MjSpec.from_file(text),
         lambda: etree.parse(text)],
        seconds,
    )  # fmt: skip
    write, lxml_write = best_of([root.to_xml_string, lambda: etree.tostring(tree)], seconds)
    compile_ours, compile_mujoco = best_of(
        [lambda: compiler.compile_composition(root),
         lambda: mujoco.MjModel.from_xml_string(xml, assets)],
        seconds=2 * seconds,
    )  # fmt: skip
    return {
        "parse": parse, "mjspec_parse": spec, "lxml_parse": lxml_parse, "write": write,
        "lxml_write": lxml_write, "write_compile": compile_ours, "mujoco_compile": compile_mujoco,
    }  # fmt: skip


def main(quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure every model; print a table and return the ratios. `quick`: a tiny budget."""
    os.chdir(os.path.dirname(os.path.abspath(__file__)))
    results: dict[str, dict[str, float]] = {}
    print(
        f"{'model':10} {'parse ms':>9} {'MjSpec':>8} {'ratio':>6} {'lxml':>7} | {'write ms':>9} "
        f"{'lxml':>7} {'ratio':>6} | {'write+compile':>13} {'MuJoCo':>8} {'ratio':>6}"
    )
    for name, path in models().items():
        t = measure(path, 0.02 if quick else 1.0)
        results[name] = {
            "parse_vs_mjspec": t["parse"] / t["mjspec_parse"],
            "parse_vs_lxml": t["parse"] / t["lxml_parse"],
            "write_vs_lxml": t["write"] / t["lxml_write"],
            "write_compile_vs_mujoco": t["write_compile"] / t["mujoco_compile"],
        }
        r = results[name]
        print(
            f"{name:10} {t['parse'] * 1e3:9.3f} {t['mjspec_parse'] * 1e3:8.3f} "
            f"{r['parse_vs_mjspec']:6.2f} {t['lxml_parse'] * 1e3:7.3f} | {t['write'] * 1e3:9.3f} "
            f"{t['lxml_write'] * 1e3:7.3f} {r['write_vs_lxml']:6.2f} | "
            f"{t['write_compile'] * 1e3:13.3f} {t['mujoco_compile'] * 1e3:8.3f} "
            f"{r['write_compile_vs_mujoco']:6.2f}"
        )
    return results


if __name__ == "__main__":
    main()
