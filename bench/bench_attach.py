"""Attach-and-compile N copies of a robot with mjcf, next to MuJoCo's own MjSpec attach of
the same copies, in the same run.

    python bench/bench_attach.py                 # ant and UR5e+2F-85, N = 1, 10, 100
    python bench/bench_attach.py 1 10            # other N
    python bench/bench_attach.py --profile 100   # cProfile of our attach of 100 ants

For each robot and N, both sides start from one loaded model (not timed) and time:
  copy     N copies of it (`copy.deepcopy(model)` / `spec.copy()`)
  attach   each copy attached to a frame of an arena (`arena.attach(copy)` with a pose
           / `arena.attach(copy_spec, frame=..., prefix=...)`)
  compile  the arena, ready to step (`mjcf.Physics.from_mjcf_model` and a first step /
           `spec.compile()`, MjData and a first step)
and prints ms per copy for each step, the total, and our total over MjSpec's, with each
side's compiled size (`mj_sizeModel`). Targets: our per-copy times stay flat as N grows
(linear totals), our total is within 5x of MjSpec's, and at most 0.8x at N = 100 arms.
The two sides run in alternating rounds and each figure is the best round of the process'
CPU time (MuJoCo's threads, which process meshes, included on both sides); one warm-up
round fills MuJoCo's mesh cache for both. Compiled sizes (bodies, joints, geoms ...) are
checked equal.

The copies of the UR5e + 2F-85 share their meshes in our scene (see `mjcf.compose.sharing`), and
not in MjSpec's, where each copy compiles to about 43 MB of mesh data and needs about
135 MB while compiling: from N = 30 on, the MjSpec side runs once, in a process of its own
limited in memory, and only when the machine has the memory free (100 copies took
13.5 GB); otherwise it is reported as skipped.
"""

from __future__ import annotations

import contextlib
import copy
import cProfile
import json
import os
import pstats
import resource
import subprocess
import sys
import time
import warnings
from pathlib import Path

import gymnasium
import mujoco

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import mjcf

REPO = Path(__file__).resolve().parents[1]
ANT = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "ant.xml"
MENAGERIE = REPO / "entities" / "menagerie"  # shipped with the package
UR5E = MENAGERIE / "universal_robots_ur5e" / "ur5e.xml"
ROBOTIQ = MENAGERIE / "robotiq_2f85" / "2f85.xml"
clock = time.process_time  # CPU time: what other processes take is not counted
ROUNDS = {1: 7, 10: 5}  # rounds per N (2 for larger N)
# MjSpec's arms: above this N in a process of its own, one round, if memory allows.
ARMS_IN_PROCESS = 20
ARM_BYTES = 140e6  # what MjSpec needs per UR5e + 2F-85 copy while compiling


# -- the two sides ---------------------------------------------------------------------------


def ours_load(robot: str) -> mjcf.RootElement:
    if robot == "ant":
        return mjcf.from_path(ANT)
    arm = mjcf.from_path(UR5E)
    arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
    return arm


def ours_run(model: mjcf.RootElement, count: int) -> tuple[dict[str, float], mujoco.MjModel]:
    times = {}
    start = clock()
    copies = [copy.deepcopy(model) for _ in range(count)]
    times["copy"] = clock() - start
    arena = mjcf.RootElement(model="arena")
    arena.worldbody.add("geom", type="plane", size=[100, 100, 0.1])
    start = clock()
    for i, robot in enumerate(copies):
        robot.model = f"r{i}"
        arena.attach(robot).pos = [2.0 * i, 0, 0]
    times["attach"] = clock() - start
    start = clock()
    physics = mjcf.Physics.from_mjcf_model(arena)
    physics.step()
    times["compile"] = clock() - start
    return times, physics.model


def spec_load(robot: str) -> mujoco.MjSpec:
    if robot == "ant":
        return mujoco.MjSpec.from_file(str(ANT))
    arm = mujoco.MjSpec.from_file(str(UR5E))
    arm.compiler.conflict = mujoco.mjtConflict.mjCONFLICT_MERGE  # adopt the gripper's options
    gripper = mujoco.MjSpec.from_file(str(ROBOTIQ))
    arm.attach(gripper, site=arm.site("attachment_site"), prefix="robotiq_2f85/")
    return arm


def spec_run(spec: mujoco.MjSpec, count: int) -> tuple[dict[str, float], mujoco.MjModel]:
    times = {}
    start = clock()
    copies = [spec.copy() for _ in range(count)]
    times["copy"] = clock() - start
    arena = mujoco.MjSpec()
    arena.modelname = "arena"
    arena.compiler.conflict = mujoco.mjtConflict.mjCONFLICT_MERGE  # adopt the copies' options
    arena.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[100, 100, 0.1])
    start = clock()
    for i, robot in enumerate(copies):
        frame = arena.worldbody.add_frame(pos=[2.0 * i, 0, 0])
        arena.attach(robot, frame=frame, prefix=f"r{i}/")
    times["attach"] = clock() - start
    start = clock()
    compiled = arena.compile()
    mujoco.mj_step(compiled, mujoco.MjData(compiled))
    times["compile"] = clock() - start
    return times, compiled


# -- measuring ---------------------------------------------------------------------------------


def best(runs: list[dict[str, float]]) -> dict[str, float]:
    out = {step: min(run[step] for run in runs) for step in runs[0]}
    out["total"] = min(sum(run.values()) for run in runs)
    return out


@contextlib.contextmanager
def quiet_stderr():
    """MuJoCo prints a warning for every attach whose options it merges: keep them out."""
    sys.stderr.flush()
    saved = os.dup(2)
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 2)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)


_SIZES = ("nbody", "njnt", "ngeom", "nu", "nq")


def measure(robot: str, count: int) -> tuple[dict[str, float], dict[str, float] | None]:
    """Best times of both sides (MjSpec's None when skipped, for memory), each with the
    compiled model's size in bytes under 'bytes'."""
    model = ours_load(robot)
    separate = robot != "ant" and count > ARMS_IN_PROCESS
    if not separate:
        with quiet_stderr():
            spec = spec_load(robot)
    ours_runs, spec_runs = [], []
    for _ in range(1 if separate else ROUNDS.get(count, 2)):
        ours_times, ours_model = ours_run(model, count)
        ours_runs.append(ours_times)
        if not separate:
            with quiet_stderr():
                spec_times, spec_model = spec_run(spec, count)
            spec_runs.append(spec_times)
    ours = {**best(ours_runs), "bytes": mujoco.mj_sizeModel(ours_model)}
    if separate:
        spec_best = spec_in_own_process(robot, count)
        if spec_best is None:
            return ours, None
    else:
        spec_best = {**best(spec_runs), "bytes": mujoco.mj_sizeModel(spec_model)}
        spec_best.update({size: getattr(spec_model, size) for size in _SIZES})
    for size in _SIZES:
        assert getattr(ours_model, size) == spec_best[size], size
    return ours, spec_best


def spec_in_own_process(robot: str, count: int) -> dict[str, float] | None:
    """MjSpec's attach + compile of `count` copies, run once in a process limited to the
    memory free now; None (and why, printed) if that is not enough."""
    needed = count * ARM_BYTES + 1e9
    free = _available_memory()
    if free < 1.2 * needed:
        print(f"{count:>5}  MjSpec  skipped: needs about {needed / 1e9:.1f} GB, "
              f"{free / 1e9:.1f} GB free")  # fmt: skip
        return None
    command = [sys.executable, __file__, "--mjspec-once", robot, str(count)]
    limit = int(min(free * 0.9, 2 * needed))
    done = subprocess.run(
        command, capture_output=True, text=True,
        preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (limit, limit)),
    )  # fmt: skip
    if done.returncode != 0:
        print(f"{count:>5}  MjSpec  failed: {done.stderr.strip().splitlines()[-1:]}")
        return None
    return json.loads(done.stdout.strip().splitlines()[-1])


def _mjspec_once(robot: str, count: int) -> None:
    """The MjSpec side once, its figures printed as JSON (for spec_in_own_process)."""
    with quiet_stderr():
        times, compiled = spec_run(spec_load(robot), count)
    times = {**best([times]), "bytes": mujoco.mj_sizeModel(compiled)}
    times.update({size: getattr(compiled, size) for size in _SIZES})
    print(json.dumps(times))


def _available_memory() -> float:
    """Bytes of memory available now (Linux' MemAvailable; 0 elsewhere)."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return 0.0


def report(robot: str, counts: list[int]) -> dict[str, dict[str, float]]:
    """Measure and print each N; returns seconds and our total over MjSpec's, by N."""
    ours_run(ours_load(robot), 2)  # warm-up: imports, MuJoCo's mesh cache
    with quiet_stderr():
        spec_run(spec_load(robot), 2)
    print(f"\n{robot}: ms per copy (best of rounds), compiled size")
    header = f"{'N':>5}  {'side':<7}" + "".join(
        f"{s:>10}" for s in ("copy", "attach", "compile", "total")
    )
    print(header + f"{'MB':>10}{'total/MjSpec':>14}")
    results = {}
    for count in counts:
        ours, spec = measure(robot, count)
        entry = {f"mjcf_{step}_s": value for step, value in ours.items() if step != "bytes"}
        entry["mjcf_model_mb"] = ours["bytes"] / 1e6
        sides = [("mjcf", ours)]
        if spec is not None:
            entry.update({f"mjspec_{s}_s": spec[s] for s in ("copy", "attach", "compile", "total")})
            entry["mjspec_model_mb"] = spec["bytes"] / 1e6
            entry["total_vs_mjspec"] = ours["total"] / spec["total"]
            sides.append(("MjSpec", spec))
        results[f"N={count}"] = entry
        for side, times in sides:
            cells = "".join(
                f"{1e3 * times[s] / count:10.3f}" for s in ("copy", "attach", "compile", "total")
            )
            ratio = f"{entry['total_vs_mjspec']:14.2f}" if side == "mjcf" and spec else ""
            print(f"{count:>5}  {side:<7}{cells}{times['bytes'] / 1e6:10.1f}{ratio}")
    return results


def profile(count: int) -> None:
    model = ours_load("ant")
    copies = [copy.deepcopy(model) for _ in range(count)]
    for i, robot in enumerate(copies):
        robot.model = f"r{i}"
    arena = mjcf.RootElement(model="arena")
    profiler = cProfile.Profile()
    profiler.enable()
    for i, robot in enumerate(copies):
        arena.attach(robot).pos = [2.0 * i, 0, 0]
    profiler.disable()
    pstats.Stats(profiler).sort_stats("cumulative").print_stats(12)


def main(argv: list[str] | None = None, quick: bool = False) -> dict[str, dict]:
    """Run as the command line says (N values, or --profile N); returns the figures by
    robot and N. `quick`: N = 1 only."""
    argv = argv or []
    if argv[:1] == ["--mjspec-once"]:
        _mjspec_once(argv[1], int(argv[2]))
        return {}
    if argv[:1] == ["--profile"]:
        profile(int(argv[1]) if len(argv) > 1 else 100)
        return {}
    counts = [int(a) for a in argv] or ([1] if quick else [1, 10, 100])
    print(f"mujoco {mujoco.__version__}, python {sys.version.split()[0]}, {os.cpu_count()} cpus")
    return {"ant": report("ant", counts), "ur5e+2f85": report("ur5e+2f85", counts)}


if __name__ == "__main__":
    main(sys.argv[1:])
