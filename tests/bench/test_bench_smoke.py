"""The benchmark suite's plumbing on tiny budgets: it runs, keeps figures and output in
its JSON, records a failing benchmark without stopping, runs the vector comparison
against other libraries or says how to install them, and profiles. No timings are
asserted."""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import signal

import pytest

from bench import bench_parse, bench_suite, profiles, real_models, suite
from bench.__main__ import main
from bench.workers import Worker, WorkerError


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
    assert vector["error"] is None and "steps/s (wall)" in vector["output"]
    assert {"n1.vector_vs_floor", "n4.vector_vs_floor", "n1.vector_vs_sync"} <= set(
        suite.ratios(vector["results"])
    )
    assert vector["results"]["n4"]["vector"]["cpu_us"] > 0
    scene = report["benchmarks"]["scene"]["results"]
    assert scene["memory"]["tree_mb"] > 0 and scene["memory"]["mjmodel_mb"] > 0
    assert "memory.tree_vs_mjmodel" in suite.ratios(scene)
    task_step = report["benchmarks"]["task_step"]["results"]
    found = suite.ratios(task_step)
    assert {"CartpoleSwingup.env_vs_raw", "Ant-v5.env_vs_raw"} <= set(found)
    assert "AntV5.reset_vs_gymnasium_reset" in found


def test_the_vector_comparison_runs_the_others_or_says_how_to_install_them(tmp_path):
    path = tmp_path / "results.json"
    command = ["vector", "--quick", "--against", "envpool,gymnasium", "--json", str(path)]
    assert main(command) == 0
    report = json.loads(path.read_text())
    vector = report["benchmarks"]["vector"]
    assert report["options"] == {"against": ["envpool", "gymnasium"]}
    assert vector["results"]["n1"]["vector_vs_gymnasium"] > 0
    if importlib.util.find_spec("envpool") is None:
        assert "envpool: not installed, skipped" in vector["output"]
        assert "pip install -e '.[bench]'" in vector["output"]
    else:
        assert vector["results"]["n1"]["vector_vs_envpool"] > 0
        assert "on the MuJoCo it bundles" in vector["results"]["sides"]["envpool"]


def test_an_unknown_side_to_run_against_is_refused(tmp_path):
    path = tmp_path / "results.json"
    assert main(["vector", "--quick", "--against", "nope", "--json", str(path)]) == 1
    error = json.loads(path.read_text())["benchmarks"]["vector"]["error"]
    assert "unknown side(s) ['nope']" in error
    with pytest.raises(SystemExit):
        main(["bind", "--against", "envpool"])  # no benchmark of these takes it


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


def test_a_side_that_raises_in_its_process_raises_with_its_traceback():
    worker = Worker("bench.vector_sides", "no_such_side")
    try:
        with pytest.raises(WorkerError, match="KeyError: 'no_such_side'"):
            worker.build(1, 1)
    finally:
        worker.close()


def test_a_side_whose_process_dies_is_named_with_its_signal():
    worker = Worker("bench.vector_sides", "no_such_side")
    try:
        worker.drop()  # the process is up and answering
        os.kill(worker._process.pid, signal.SIGKILL)
        worker._process.join(timeout=30)
        with pytest.raises(WorkerError, match=r"side 'no_such_side'.s process died \(killed by "
                           r"signal 9\) before answering 'round'"):  # fmt: skip
            worker.round(1)
    finally:
        worker.close()


def test_parse_measures_real_files_and_the_first_call():
    results = bench_parse.main("ant", quick=True)
    ant = results["ant"]
    assert ant["parse_ms"] > 0 and ant["first_parse_ms"] > 0 and ant["mjspec_parse_ms"] > 0
    assert {"parse_vs_mjspec", "first_parse_vs_mjspec"} <= set(suite.ratios(results["ant"]))
    with pytest.raises(KeyError, match="nope"):
        real_models.files("nope")


def test_profile_charges_each_sample_to_its_innermost_python_function_and_our_line():
    raw = "\n".join(
        [
            "main (bench/profiles.py:1);_sampled_loop (bench/profiles.py:90);"
            "step (composer/environment.py:300);step (mjcf/sim/physics.py:346);"
            "mj_step2 (mujoco/libmujoco.so.4.0.0) 6",
            "main (bench/profiles.py:1);_sampled_loop (bench/profiles.py:90);"
            "step (composer/environment.py:301);clip (numpy/_core/fromnumeric.py:49) 3",
            "main (bench/profiles.py:1);_sampled_loop (bench/profiles.py:90);"
            "_left_out (bench/profiles.py:80);reset (composer/environment.py:250) 50",
            "main (bench/profiles.py:1);_timed_loop (bench/profiles.py:70) 40",
            "main (bench/profiles.py:1);_sampled_loop (bench/profiles.py:90);"
            "from_path (mjcf/io/parser.py:79);os_fspath (libpython3.11.so.1.0);"
            "gc_collect_main (libpython3.11.so.1.0);free (libc.so.6) 2",
        ]
    )
    found = profiles.charge(raw)
    assert found["total"]["all"] == 11  # resets and the timed stretch left out
    assert found["self"] == {
        "mjcf/sim/physics.py:step": 6,
        "numpy/_core/fromnumeric.py:clip": 3,
        profiles.GARBAGE: 2,
    }
    assert found["mujoco"] == {"mjcf/sim/physics.py:step": 6}
    assert found["lines"] == {
        "mjcf/sim/physics.py:346 (step)": 6,
        "composer/environment.py:301 (step)": 3,
        profiles.GARBAGE: 2,
    }
    assert found["inclusive"]["composer/environment.py:step"] == 9
    assert found["inclusive"]["mjcf/io/parser.py:from_path"] == 2


def test_cprofile_profiles_a_step(capsys):
    profiles.main(["step", "CartpoleSwingup", "--seconds", "0.4", "--cprofile", "--top", "40"])
    out = capsys.readouterr().out
    assert "calls under cProfile" in out and "environment.py" in out


@pytest.mark.skipif(
    shutil.which("py-spy") is None, reason="py-spy is not installed: pip install -e '.[bench]'"
)
def test_py_spy_profiles_a_step_in_microseconds_per_call(capsys):
    profiles.main(["step", "CartpoleSwingup", "--seconds", "1", "--lines", "5"])
    out = capsys.readouterr().out
    assert "us CPU per call" in out
    assert "composer/environment.py:Environment.step" in out  # inclusive, all of a step


def test_the_suite_step_benchmark_measures_three_sides(tmp_path):
    pytest.importorskip("dm_env")
    from tests import dm_control_wheel

    dm_control_wheel.wheel()  # skips when the index cannot give dm_control's wheel
    path = tmp_path / "results.json"
    assert main(["suite_step", "--quick", "--json", str(path)]) == 0
    results = json.loads(path.read_text())["benchmarks"]["suite_step"]["results"]
    found = suite.ratios(results)
    assert {"cartpole-swingup.ours_vs_raw", "cartpole-swingup.ours_vs_dm_control"} <= set(found)


def test_the_suite_comparison_runs_ours_the_floor_envpool_and_gymnasium(tmp_path):
    pytest.importorskip("envpool", reason="envpool is not installed: pip install -e '.[bench]'")
    path = tmp_path / "results.json"
    command = ["suite", "--quick", "--against", "envpool,gymnasium", "--json", str(path)]
    assert main(command) == 0
    entry = json.loads(path.read_text())["benchmarks"]["suite"]
    assert entry["error"] is None and "envpool CartpoleSwingup-v1" in entry["output"]
    results = entry["results"]
    assert set(results["sides"]) == {"vector", "floor", "batch", "envpool", "gymnasium"}
    assert "on the MuJoCo it bundles" in results["sides"]["envpool"]
    found = suite.ratios(results)
    for num_envs in (1, 4):
        for ratio in ("vector_vs_envpool", "vector_vs_floor", "vector_vs_gymnasium"):
            assert found[f"tasks.cartpole-swingup.n{num_envs}.{ratio}"] > 0
        size = results["tasks"]["cartpole-swingup"][f"n{num_envs}"]
        assert len(size["load"]) == 2
        # Each threaded side on 1 and min(N, CPUs) threads, reported at the better count.
        counts = sorted({1, min(num_envs, results["cpus"])})
        assert {f"vector@{n}" for n in counts} | {f"envpool@{n}" for n in counts} <= set(
            size["runs"]
        )
        assert size["vector"]["threads"] in counts and size["envpool"]["threads"] in counts
        assert size["vector_default_threads"] in counts
        # What the floor goal leaves beyond MuJoCo's batch loop, and what ours spends there.
        batch = size["batch"]["cpu_us"]
        room = (size["floor"]["cpu_us"] / 0.95 - batch) * num_envs
        assert size["room_us_a_call"] == pytest.approx(room)
        ours = (size["vector"]["cpu_us"] - batch) * num_envs
        assert size["ours_over_batch_us_a_call"] == pytest.approx(ours)
    assert "room_us_a_call" in entry["output"]


def test_the_suite_comparison_refuses_a_task_that_is_not_registered():
    with pytest.raises(ValueError, match=r"unknown suite task\(s\) \['cheetah-sprint'\]"):
        bench_suite.main(quick=True, subjects=("cheetah-run", "cheetah-sprint"))
