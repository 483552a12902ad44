"""Reading and writing real MJCF files with mjcf, next to MuJoCo's and lxml's own, same run.

    python bench/bench_parse.py
    python bench/bench_parse.py rodent cmu_v2020     # some of the files

The files (`bench.real_models`): gymnasium's humanoid and ant, the Menagerie UR5e and
2F-85 we ship, and dm_control's walkers (rodent, CMU humanoid 2020 and 2019, dog,
fruitfly, jumping ball) taken from its published wheel at run time. For each:
`mjcf.from_path` against `mujoco.MjSpec.from_file` and a bare `lxml.etree.parse` of the
same file, the median of alternating rounds of the process' CPU time (time other
processes take from this one is not counted) with the best round and the rounds' spread;
the first call of each in a fresh process (imports done, nothing read yet: what a
script that loads one model pays), median of 3 processes; `to_xml_string()` against
lxml's `tostring` of the parsed file; and writing + compiling
(`mjcf.Physics.from_mjcf_model`'s work) against `mujoco.MjModel.from_xml_string` of the
same text. Then what reading may leave for later, on a model just read: the first edit
(find a body deep in the tree by name and move it) and the first write
(`to_xml_string()`). Write, compile and first use are best rounds.
Targets: parse no slower than MjSpec (issue 28), write within 5x of lxml, write +
compile within 1.3x of MuJoCo's compile.
"""

from __future__ import annotations

import multiprocessing
import os
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))  # run from a checkout

import mujoco  # noqa: E402
from lxml import etree  # noqa: E402

import mjcf  # noqa: E402
from bench import real_models, rounds  # noqa: E402
from mjcf.sim import compiler  # noqa: E402

clock = time.process_time
FIRST_CALL_PROCESSES = 3


def timed_rounds(functions: list[Callable[[], object]], seconds: float) -> list[list[float]]:
    """Seconds of each call of each function, called in alternating rounds for `seconds`
    (at least 3 rounds)."""
    found: list[list[float]] = [[] for _ in functions]
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline or len(found[0]) < 3:
        for i, function in enumerate(functions):
            start = clock()
            function()
            found[i].append(clock() - start)
    return found


def best_of(functions: list[Callable[[], object]], seconds: float = 1.0) -> list[float]:
    """Best time per call of each function, timed in alternating rounds for `seconds`."""
    return [min(times) for times in timed_rounds(functions, seconds)]


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


def _first_calls(path: str, ours_first: bool) -> tuple[float, float]:
    """In a fresh process: CPU seconds of the process' first `mjcf.from_path` and first
    `MjSpec.from_file` of `path`, in the order given."""
    calls = [lambda: mjcf.from_path(path), lambda: mujoco.MjSpec.from_file(path)]
    found = []
    for call in calls if ours_first else calls[::-1]:
        start = clock()
        call()
        found.append(clock() - start)
    return (found[0], found[1]) if ours_first else (found[1], found[0])


def first_calls(path: Path, processes: int) -> dict[str, float]:
    """Median first-call seconds of ours and of MjSpec over `processes` fresh processes,
    which alternate which of the two reads first."""
    context = multiprocessing.get_context("spawn")
    ours, spec = [], []
    for k in range(processes):
        with context.Pool(1) as pool:
            a, b = pool.apply(_first_calls, (str(path), k % 2 == 0))
        ours.append(a)
        spec.append(b)
    return {"first_parse": statistics.median(ours), "first_mjspec_parse": statistics.median(spec)}


def measure(path: Path, seconds: float = 1.0, processes: int = 3) -> dict[str, float]:
    """Seconds per call of each operation on one model, ours and the references, each
    timed for about `seconds` (compiling for twice that)."""
    text = str(path)
    tree = etree.parse(text)
    root = mjcf.from_path(path)
    xml = root.to_xml_string()
    assets = root.get_assets()
    parse, spec, lxml_parse = (
        rounds.spread(times)
        for times in timed_rounds(
            [lambda: mjcf.from_path(path), lambda: mujoco.MjSpec.from_file(text),
             lambda: etree.parse(text)],
            seconds,
        )
    )  # fmt: skip
    write, lxml_write = best_of([root.to_xml_string, lambda: etree.tostring(tree)], seconds)
    compile_ours, compile_mujoco = best_of(
        [lambda: compiler.compile_composition(root),
         lambda: mujoco.MjModel.from_xml_string(xml, assets)],
        seconds=2 * seconds,
    )  # fmt: skip
    return {
        "parse": parse["median"], "parse_best": parse["best"], "parse_spread": parse["spread"],
        "mjspec_parse": spec["median"], "mjspec_best": spec["best"],
        "mjspec_spread": spec["spread"], "lxml_parse": lxml_parse["median"], "write": write,
        "lxml_write": lxml_write, "write_compile": compile_ours, "mujoco_compile": compile_mujoco,
        **first_calls(path, processes), **first_use(path, seconds),
    }  # fmt: skip


def main(*names: str, quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure the files `names` (all by default); print a table and return the ratios and
    times (ms). `quick`: a tiny budget on the first two files."""
    os.chdir(os.path.dirname(os.path.abspath(__file__)))
    chosen, note = real_models.files(*names)
    if note:
        print(note)
    if quick:
        chosen = dict(list(chosen.items())[:2])
    results: dict[str, dict[str, float]] = {}
    print(
        f"{'model':12} {'parse ms':>9} {'MjSpec':>7} {'ratio':>5} {'spread':>6} {'lxml':>6} | "
        f"{'1st call':>8} {'MjSpec':>6} {'ratio':>5} | {'write':>6} {'ratio':>5} | "
        f"{'wr+comp':>7} {'ratio':>5} | {'1st edit':>8} {'1st wr':>6}"
    )
    for name, path in chosen.items():
        t = measure(path, 0.02 if quick else 1.0, 1 if quick else FIRST_CALL_PROCESSES)
        results[name] = r = {
            "parse_vs_mjspec": t["parse"] / t["mjspec_parse"],
            "parse_best_vs_mjspec_best": t["parse_best"] / t["mjspec_best"],
            "first_parse_vs_mjspec": t["first_parse"] / t["first_mjspec_parse"],
            "parse_vs_lxml": t["parse"] / t["lxml_parse"],
            "write_vs_lxml": t["write"] / t["lxml_write"],
            "write_compile_vs_mujoco": t["write_compile"] / t["mujoco_compile"],
            "parse_spread": t["parse_spread"],
            "mjspec_spread": t["mjspec_spread"],
            **{f"{key}_ms": value * 1e3 for key, value in t.items() if "spread" not in key},
        }
        print(
            f"{name:12} {r['parse_ms']:9.3f} {r['mjspec_parse_ms']:7.3f} "
            f"{r['parse_vs_mjspec']:5.2f} {max(r['parse_spread'], r['mjspec_spread']):6.0%} "
            f"{r['lxml_parse_ms']:6.3f} | {r['first_parse_ms']:8.2f} "
            f"{r['first_mjspec_parse_ms']:6.2f} {r['first_parse_vs_mjspec']:5.2f} | "
            f"{r['write_ms']:6.3f} {r['write_vs_lxml']:5.2f} | {r['write_compile_ms']:7.2f} "
            f"{r['write_compile_vs_mujoco']:5.2f} | {r['first_edit_ms']:8.3f} "
            f"{r['first_write_ms']:6.3f}"
        )
    return results


if __name__ == "__main__":
    main(*sys.argv[1:])
