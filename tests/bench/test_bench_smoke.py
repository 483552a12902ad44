"""The benchmark suite's plumbing on tiny budgets: it runs, keeps figures and output in
its JSON, and records a failing benchmark without stopping. No timings are asserted."""

from __future__ import annotations

import json

import pytest

from bench import suite
from bench.__main__ import main


def test_quick_suite_writes_figures_ratios_and_output(tmp_path):
    path = tmp_path / "results.json"
    names = ["bind", "scene", "large", "vector", "task_step"]
    assert main([*names, "--quick", "--json", str(path)]) == 0
    report = json.loads(path.read_text())
    assert report["quick"] and report["machine"]["mujoco"]
    assert list(report["benchmarks"]) == names
    large = report["benchmarks"]["large"]["results"]
    assert large["2000 bodies"]["tree_mb"] > 0 and large["2000 bodies"]["parse_s"] > 0
    vector = report["benchmarks"]["vector"]
    assert vector["error"] is None and "env-steps/s" in vector["output"]
    assert {"vector_vs_raw_batch", "vector_vs_sync"} <= set(vector["results"])
    scene = report["benchmarks"]["scene"]["results"]
    assert scene["memory"]["tree_mb"] > 0 and scene["memory"]["mjmodel_mb"] > 0
    assert "memory.tree_vs_mjmodel" in suite.ratios(scene)
    task_step = report["benchmarks"]["task_step"]["results"]
    assert "CartpoleSwingup.env_vs_raw" in suite.ratios(task_step)


def test_a_failing_benchmark_is_recorded_and_the_rest_run(tmp_path, monkeypatch):
    monkeypatch.setattr(
        suite, "BENCHMARKS", {"broken": "bench.no_such_benchmark", **suite.BENCHMARKS}
    )
    path = tmp_path / "results.json"
    assert main(["broken", "bind", "--quick", "--json", str(path)]) == 1
    report = json.loads(path.read_text())
    assert "No module named" in report["benchmarks"]["broken"]["error"]
    assert report["benchmarks"]["bind"]["error"] is None


def test_unknown_benchmark_names_are_refused():
    with pytest.raises(KeyError, match="nope"):
        suite.run(["nope"])
