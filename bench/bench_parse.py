"""Reading and writing MJCF with mjcf, next to MuJoCo's and lxml's own, same run.

    python bench/bench_parse.py

For each model (gymnasium's humanoid and ant, the menagerie UR5e and 2F-85, and two
synthetic models of the kind of dm_control's CMU humanoid and rodent, see
`bench/synthetic.py`): `mjcf.from_path` against `mujoco.MjSpec.from_file` and a bare
`lxml.etree.parse` of the same file; `to_xml_string()` against lxml's `tostring` of the
parsed file; and writing + compiling (`mjcf.Physics.from_mjcf_model`'s work) against
`mujoco.MjModel.from_xml_string` of the same text. Then what reading may leave for
later, on a model just read: the first edit (find a body deep in the tree by name and
move it) and the first write (`to_xml_string()`). Each figure is the best of alternating
rounds of the process' CPU time (`time.process_time`: time other processes take from
this one is not counted, and both sides are measured alike).
Targets: parse no slower than MjSpec, write within 5x of lxml, write + compile within
1.3x of MuJoCo's compile.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))  # run from a checkout

import gymnasium  # noqa: E402
import mujoco  # noqa: E402
from lxml import etree  # noqa: E402

import mjcf  # noqa: E402
from bench import synthetic  # noqa: E402
from mjcf import compiler  # noqa: E402

clock = time.process_time
GYM = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MENAGERIE = REPO / "entities" / "menagerie"  # shipped with the package


def best_of(functions: list[Callable[[], object]], seconds: float = 1.0) -> list[float]:
    """Best time per call of each function, timed in alternating rounds for `seconds`."""
    best = [float("inf")] * len(functions)
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline:
        for i, function in enumerate(functions):
            start = clock()
            function()
            best[i] = min(best[i], clock() - start)
    return best


def models(folder: Path) -> dict[str, Path]:
    """The models measured: gymnasium's, the shipped menagerie robots, and the synthetic
    ones (written into `folder`)."""
    found = {
        "humanoid": GYM / "humanoid.xml",
        "ant": GYM / "ant.xml",
        "ur5e": MENAGERIE / "universal_robots_ur5e" / "ur5e.xml",
        "2f85": MENAGERIE / "robotiq_2f85" / "2f85.xml",
    }
    for shape in (synthetic.CMU_HUMANOID, synthetic.RODENT):
        path = folder / f"{shape.name}.xml"
        path.write_text(synthetic.creature_xml(shape))
        found[shape.name] = path
    return found


def deepest_body(path: Path) -> str:
    """The name of the body nested deepest in the file (the first of them)."""
    tree = etree.parse(str(path))
    bodies = [(len(list(b.iterancestors())), b.get("name")) for b in tree.iter("body")]
    return max((depth, -i, name) for i, (depth, name) in enumerate(bodies) if name)[2]


def first_use(path: Path, seconds: float) -> dict[str, float]:
    """Best seconds of the first edit and of the first write of a model just read."""
    name = deepest_body(path)
    best = {"first_edit": float("inf"), "first_write": float("inf")}
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline:
        root = mjcf.from_path(path)
        start = clock()
        root.find("body", name).pos = [0.1, 0.2, 0.3]
        best["first_edit"] = min(best["first_edit"], clock() - start)
        root = mjcf.from_path(path)
        start = clock()
        root.to_xml_string()
        best["first_write"] = min(best["first_write"], clock() - start)
    return best


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
        **first_use(path, seconds),
    }  # fmt: skip


def main(quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure every model; print a table and return the ratios. `quick`: a tiny budget."""
    os.chdir(os.path.dirname(os.path.abspath(__file__)))
    results: dict[str, dict[str, float]] = {}
    print(
        f"{'model':11} {'parse ms':>9} {'MjSpec':>8} {'ratio':>6} {'lxml':>7} | {'write ms':>9} "
        f"{'lxml':>7} {'ratio':>6} | {'write+compile':>13} {'MuJoCo':>8} {'ratio':>6} | "
        f"{'1st edit':>8} {'1st write':>9}"
    )
    with tempfile.TemporaryDirectory() as folder:
        for name, path in models(Path(folder)).items():
            t = measure(path, 0.02 if quick else 1.0)
            results[name] = {
                "parse_vs_mjspec": t["parse"] / t["mjspec_parse"],
                "parse_vs_lxml": t["parse"] / t["lxml_parse"],
                "write_vs_lxml": t["write"] / t["lxml_write"],
                "write_compile_vs_mujoco": t["write_compile"] / t["mujoco_compile"],
                "first_edit_ms": t["first_edit"] * 1e3,
                "first_write_ms": t["first_write"] * 1e3,
            }
            r = results[name]
            print(
                f"{name:11} {t['parse'] * 1e3:9.3f} {t['mjspec_parse'] * 1e3:8.3f} "
                f"{r['parse_vs_mjspec']:6.2f} {t['lxml_parse'] * 1e3:7.3f} | "
                f"{t['write'] * 1e3:9.3f} {t['lxml_write'] * 1e3:7.3f} {r['write_vs_lxml']:6.2f} | "
                f"{t['write_compile'] * 1e3:13.3f} {t['mujoco_compile'] * 1e3:8.3f} "
                f"{r['write_compile_vs_mujoco']:6.2f} | {r['first_edit_ms']:8.3f} "
                f"{r['first_write_ms']:9.3f}"
            )
    return results


if __name__ == "__main__":
    main()
