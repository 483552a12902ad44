"""A very large model: reading and writing grow linearly up to 100,000 bodies, and the
tree holds a few times the memory of the compiled model.

    python bench/bench_large.py            # 50, 100, 250, 500 chains of 200 bodies

The model is `chains` chains of 200 nested bodies (each with a hinge and a capsule) side
by side: 500 chains are 100,000 bodies, 300,000 elements, nested 200 deep. For each size,
in a process of its own (so that memory figures start from the same point), in seconds
of the process' CPU time (one run each: on a machine others use, wall time would
measure them):
  parse   `mjcf.from_path` of the file
  write   the first `to_xml_string()` of the model just read (which builds every element)
  memory  what the process holds after both (resident set growth: Python objects and the
          parsed XML), against `mujoco.mj_sizeModel` of the compiled model.
MuJoCo's own parser and compiler take time quadratic in the depth of these chains (36 s
to compile 50 chains here), so the compiled size is measured for 2, 4 and 8 chains,
where it is exactly linear in the number of chains, and extrapolated. Targets: parse +
write of 100,000 bodies under 10 s, time per body flat, tree under 5x the MjModel.
"""

from __future__ import annotations

import functools
import gc
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))  # run from a checkout

from bench import synthetic  # noqa: E402

LINKS = 200


def rss_bytes() -> int:
    """Resident set size of this process (Linux)."""
    with open("/proc/self/statm") as handle:
        return int(handle.read().split()[1]) * resource.getpagesize()


def _measure_once(path: str) -> dict[str, float]:
    """Parse and write `path` in this process (see the module docstring)."""
    import mjcf

    mjcf.from_xml_string("<mujoco/>").to_xml_string()  # imports, the XML Schema
    gc.collect()
    before = rss_bytes()
    start = time.process_time()
    model = mjcf.from_path(path)
    parsed = time.process_time()
    text = model.to_xml_string()
    written = time.process_time()
    del text
    gc.collect()
    return {"parse_s": parsed - start, "write_s": written - parsed,
            "tree_mb": (rss_bytes() - before) / 1e6}  # fmt: skip


def compiled_mb(chains: int) -> float:
    """`mj_sizeModel` of `chains` chains, in MB: extrapolated from 2, 4 and 8 chains
    (checked linear)."""
    base, per_chain = _compiled_size_line()
    return (base + chains * per_chain) / 1e6


@functools.cache
def _compiled_size_line() -> tuple[float, float]:
    sizes = {
        n: mujoco.mj_sizeModel(mujoco.MjModel.from_xml_string(synthetic.chains_xml(n, LINKS)))
        for n in (2, 4, 8)
    }
    per_chain = (sizes[4] - sizes[2]) / 2
    predicted = sizes[4] + 4 * per_chain
    assert abs(predicted - sizes[8]) <= 1e-3 * sizes[8], sizes
    return sizes[2] - 2 * per_chain, per_chain


def main(quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure each size in its own process; print a table, return the figures."""
    counts = [5, 10] if quick else [50, 100, 250, 500]
    results = {}
    print(f"{'bodies':>8} {'parse s':>8} {'write s':>8} {'total s':>8} {'us/body':>8} "
          f"{'tree MB':>8} {'MjModel MB':>11} {'ratio':>6}")  # fmt: skip
    with tempfile.TemporaryDirectory() as folder:
        for chains in counts:
            path = Path(folder) / f"chains{chains}.xml"
            path.write_text(synthetic.chains_xml(chains, LINKS))
            done = subprocess.run(
                [sys.executable, __file__, "--once", str(path)],
                capture_output=True, text=True, check=True,
            )  # fmt: skip
            figures = json.loads(done.stdout.strip().splitlines()[-1])
            bodies = chains * LINKS
            total = figures["parse_s"] + figures["write_s"]
            figures["mjmodel_mb"] = compiled_mb(chains)
            figures["us_per_body"] = 1e6 * total / bodies
            figures["tree_vs_mjmodel"] = figures["tree_mb"] / figures["mjmodel_mb"]
            results[f"{bodies} bodies"] = figures
            print(f"{bodies:>8} {figures['parse_s']:8.2f} {figures['write_s']:8.2f} "
                  f"{total:8.2f} {figures['us_per_body']:8.1f} {figures['tree_mb']:8.1f} "
                  f"{figures['mjmodel_mb']:11.1f} {figures['tree_vs_mjmodel']:6.2f}")  # fmt: skip
    return results


if __name__ == "__main__":
    if sys.argv[1:2] == ["--once"]:
        print(json.dumps(_measure_once(sys.argv[2])))
    else:
        main(quick="--quick" in sys.argv)
