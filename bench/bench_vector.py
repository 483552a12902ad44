"""Gymnasium's Ant stepped N at a time: composer.VectorEnvironment against MuJoCo's floor,
envpool and gymnasium, at N = 1, 8, 32, 128, in one run.

    python -m bench vector --against envpool,gymnasium
    python bench/bench_vector.py --against envpool --sizes 1,8

The sides (`bench.vector_sides`, which says what each one runs): ours (`vector`), the
floor (mujoco.batch with the same per-step numpy work), MuJoCo's physics alone
(mujoco.rollout, one call a round), our single environments in gymnasium's
SyncVectorEnv (`sync`), the shipped AntRun-v0 vectorized and in SyncVectorEnv, and with
`--against`, envpool's Ant-v5 and gymnasium's own Ant-v5 in SyncVectorEnv. Every side
runs in a process of its own (`bench.workers`), on `nthread` threads where it has threads
(the CPUs this process may use), and the rounds alternate between them; a round resets
(not timed), then runs about 4096 environment steps (at most 800 control steps, under
the 1000-step limits of gymnasium's and envpool's episodes).

Figures: CPU time per environment step (the process', its threads included) is the robust
one on a shared machine: best and median round, and the rounds' spread; throughput
(environment steps per second of wall time, best round) is what a user sees, and follows
the load of the machine. `<side>_vs_floor` is that side's throughput relative to the floor
(CPU figure): 1.0 is the floor's, higher is faster. `vector_vs_<side>` is ours relative to
that side's: above 1.0 we are faster. Goals (issue 28): vector >= envpool at every N, and
>= 0.95 of the floor at N >= 32.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

from bench import rounds, vector_sides
from bench.workers import Worker

SIZES = (1, 8, 32, 128)
AGAINST = ("envpool", "gymnasium")
BASE_SIDES = ("vector", "floor", "physics", "sync", "antrun_vector", "antrun_sync")
ROUNDS = 7
ENV_STEPS = 4096
MAX_STEPS = 800


def steps_per_round(num_envs: int, env_steps: int = ENV_STEPS) -> int:
    """Control steps of a round of about `env_steps` environment steps."""
    return max(1, min(MAX_STEPS, math.ceil(env_steps / num_envs)))


def usable_cpus() -> int:
    """The CPUs this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def _figures(times: list[tuple[float, float]], env_steps: int) -> dict[str, float]:
    cpu = rounds.spread([c / env_steps * 1e6 for _, c in times])
    return {
        "cpu_us": cpu["best"], "cpu_us_median": cpu["median"], "cpu_spread": cpu["spread"],
        "steps_per_s": env_steps / min(w for w, _ in times),
    }  # fmt: skip


def _ratios(found: dict[str, dict[str, float]]) -> dict[str, float]:
    """Each side against the floor, and ours against each side (CPU figures; see the
    module docstring), and ours against envpool in wall time too."""
    ratios = {}
    floor = found.get("floor")
    ours = found.get("vector")
    for side, figures in found.items():
        if side.startswith("antrun"):
            continue  # another model
        if floor is not None and side != "floor":
            ratios[f"{side}_vs_floor"] = floor["cpu_us"] / figures["cpu_us"]
        if ours is not None and side != "vector":
            ratios[f"vector_vs_{side}"] = figures["cpu_us"] / ours["cpu_us"]
    if ours is not None and "envpool" in found:
        ratios["vector_vs_envpool_wall"] = ours["steps_per_s"] / found["envpool"]["steps_per_s"]
    if "antrun_vector" in found and "antrun_sync" in found:
        ratios["antrun_vector_vs_sync"] = (
            found["antrun_sync"]["cpu_us"] / found["antrun_vector"]["cpu_us"]
        )
    return ratios


def _print_size(num_envs: int, steps: int, found: dict[str, dict[str, float]]) -> None:
    print(f"\nN = {num_envs} ({steps} control steps a round)")
    print(f"  {'side':14} {'CPU us/step':>11} {'median':>8} {'spread':>7} "
          f"{'steps/s (wall)':>15} {'vs floor':>9}")  # fmt: skip
    floor = found.get("floor")
    for side, f in found.items():
        same_model = floor is not None and not side.startswith("antrun")
        relative = f"{floor['cpu_us'] / f['cpu_us']:9.2f}" if same_model else ""
        print(f"  {side:14} {f['cpu_us']:11.1f} {f['cpu_us_median']:8.1f} "
              f"{f['cpu_spread']:7.0%} {f['steps_per_s']:15.0f} {relative}")  # fmt: skip


def main(
    quick: bool = False, against: tuple[str, ...] = (), sizes: tuple[int, ...] = SIZES
) -> dict[str, Any]:
    """Measure and print every size; returns the figures and ratios by size ('n32': ...).
    `quick`: N = 1 and 4, one round of a few steps. Raises ValueError for an unknown
    side in `against`."""
    unknown = set(against) - set(AGAINST)
    if unknown:
        raise ValueError(f"unknown side(s) {sorted(unknown)} to run against; known: {AGAINST}")
    if quick:
        sizes, round_count, env_steps = tuple(min(n, 4) for n in sizes[:2]), 1, 8
    else:
        round_count, env_steps = ROUNDS, ENV_STEPS
    nthread = usable_cpus()
    sides = list(BASE_SIDES)
    for side in against:
        how = vector_sides.missing(side)
        if how is None:
            sides.append(side)
        else:
            print(f"{side}: not installed, skipped; to compare with it: {how}")
    workers = {side: Worker("bench.vector_sides", side) for side in sides}
    results: dict[str, Any] = {"nthread": nthread, "sides": {}}
    try:
        print(f"Gymnasium's Ant-v5 model, {vector_sides.SUBSTEPS} physics steps per control "
              f"step, {nthread} threads for the sides that have threads")  # fmt: skip
        for side, worker in workers.items():
            results["sides"][side] = worker.describe()
            print(f"  {side:14} {results['sides'][side]}")
        for num_envs in sizes:
            steps = steps_per_round(num_envs, env_steps)
            for worker in workers.values():
                worker.build(num_envs, nthread)
            timed = rounds.alternate(
                {side: (lambda w=worker, s=steps: w.round(s)) for side, worker in workers.items()},
                round_count,
            )
            found = {side: _figures(t, steps * num_envs) for side, t in timed.items()}
            _print_size(num_envs, steps, found)
            ratios = _ratios(found)
            print("  " + ", ".join(f"{key} {value:.2f}" for key, value in ratios.items()))
            results[f"n{num_envs}"] = {**found, **ratios}
    finally:
        for worker in workers.values():
            worker.close()
    return results


def _command_line(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", default="", help=f"comma-separated: {', '.join(AGAINST)}")
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)), help="numbers of envs")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    return {
        "quick": args.quick,
        "against": tuple(filter(None, args.against.split(","))),
        "sizes": tuple(int(n) for n in args.sizes.split(",")),
    }


if __name__ == "__main__":
    main(**_command_line())
