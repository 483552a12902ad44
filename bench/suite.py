"""The benchmark suite: every bench_*.py in one run, its figures kept as JSON.

    results = run(['vector', 'scene'], quick=True, json_path=Path('out.json'))
    results['benchmarks']['vector']['results']['vector_vs_raw_batch']

Each benchmark is a module's `main(quick=..., **options)` returning a dict of figures
(ratios are the keys with '_vs_'); what it prints is shown and kept too. A benchmark that
raises is recorded with its traceback and the others still run. An option goes to the
benchmarks whose `main` takes it (`against`: bench_vector's other sides).
"""

from __future__ import annotations

import contextlib
import datetime
import importlib
import inspect
import io
import json
import os
import platform
import subprocess
import sys
import time
import traceback
from pathlib import Path
from typing import Any, TextIO

REPO = Path(__file__).resolve().parents[1]
RESULTS = REPO / "bench" / "results"

# name -> module: the order they run in
BENCHMARKS = {
    "parse": "bench.bench_parse",
    "bind": "bench.bench_bind",
    "env_step": "bench.bench_env_step",
    "task_step": "bench.bench_task_step",
    "suite_step": "bench.bench_suite_step",
    "render": "bench.bench_render",
    "attach": "bench.bench_attach",
    "scene": "bench.bench_scene",
    "large": "bench.bench_large",
    "vector": "bench.bench_vector",
    "ray": "bench.bench_ray",
    "ray_learning": "bench.bench_ray_learning",
}


class _Tee(io.TextIOBase):
    """Writes to a stream and keeps a copy."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self.kept = io.StringIO()

    def write(self, text: str) -> int:
        self.stream.write(text)
        return self.kept.write(text)

    def flush(self) -> None:
        self.stream.flush()


def default_path() -> Path:
    """bench/results/<UTC timestamp>.json."""
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    return RESULTS / f"{stamp}.json"


def machine() -> dict[str, Any]:
    """What the figures depend on: versions, CPUs, load, the commit measured."""
    import mujoco
    import numpy

    try:
        commit = subprocess.run(
            ["git", "-C", str(REPO), "rev-parse", "HEAD"], capture_output=True, text=True
        ).stdout.strip()
    except OSError:
        commit = ""
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return {
        "commit": commit, "python": platform.python_version(), "mujoco": mujoco.__version__,
        "numpy": numpy.__version__, "platform": platform.platform(), "cpus": os.cpu_count(),
        "usable_cpus": usable,
        "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
    }  # fmt: skip


def ratios(results: Any, prefix: str = "") -> dict[str, float]:
    """Every '_vs_' figure of a benchmark's (nested) results, by dotted path."""
    found: dict[str, float] = {}
    if isinstance(results, dict):
        for key, value in results.items():
            path = f"{prefix}.{key}" if prefix else str(key)
            if isinstance(value, dict):
                found.update(ratios(value, path))
            elif "_vs_" in str(key) and isinstance(value, int | float):
                found[path] = float(value)
    return found


def _taking(module: Any, options: dict[str, Any]) -> dict[str, Any]:
    """The options that `module.main` takes."""
    parameters = inspect.signature(module.main).parameters
    return {key: value for key, value in options.items() if key in parameters}


def run(
    names: list[str] | None = None,
    quick: bool = False,
    json_path: Path | None = None,
    options: dict[str, Any] | None = None,
):
    """Run the benchmarks `names` (all by default) with `options` and write the JSON
    (default `default_path()`); returns what it wrote. Raises KeyError for an unknown
    name, ValueError for an option none of them takes."""
    names = list(BENCHMARKS) if names is None else names
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        raise KeyError(f"unknown benchmark(s) {unknown}; known: {list(BENCHMARKS)}")
    options = options or {}
    if options:
        modules = [importlib.import_module(BENCHMARKS[n]) for n in names]
        taken = {key for module in modules for key in _taking(module, options)}
        if set(options) - taken:
            raise ValueError(f"no benchmark of {names} takes {sorted(set(options) - taken)}")
    json_path = Path(json_path or default_path()).resolve()
    cwd = os.getcwd()  # a benchmark may change it (bench_parse does)
    report: dict[str, Any] = {
        "machine": machine(), "quick": quick, "options": options, "benchmarks": {}
    }  # fmt: skip
    for name in names:
        print(f"\n== {name} " + "=" * (70 - len(name)), flush=True)
        tee = _Tee(sys.stdout)
        entry: dict[str, Any] = {"results": None, "error": None}
        start = time.perf_counter()
        try:
            with contextlib.redirect_stdout(tee):
                module = importlib.import_module(BENCHMARKS[name])
                entry["results"] = module.main(quick=quick, **_taking(module, options))
        except Exception:
            entry["error"] = traceback.format_exc()
            print(entry["error"], file=sys.stderr)
        finally:
            os.chdir(cwd)
        entry["seconds"] = time.perf_counter() - start
        entry["output"] = tee.kept.getvalue()
        report["benchmarks"][name] = entry
    print("\n== ratios (ours / raw MuJoCo unless named otherwise) " + "=" * 18)
    for name, entry in report["benchmarks"].items():
        for path, value in ratios(entry["results"]).items():
            print(f"{name:9} {path:60} {value:8.2f}")
        if entry["error"]:
            print(f"{name:9} FAILED: {entry['error'].strip().splitlines()[-1]}")
    json_path.parent.mkdir(parents=True, exist_ok=True)
    json_path.write_text(json.dumps(report, indent=1, default=float))
    print(f"\nwrote {json_path}")
    return report
