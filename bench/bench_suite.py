"""The Control Suite stepped N at a time: our batched suite tasks against MuJoCo's floor,
envpool's C++ suite and gymnasium's SyncVectorEnv, at N = 1, 8, 32, 128, in one run
(issue 39).

    python -m bench suite --against envpool,gymnasium
    python bench/bench_suite.py --against envpool --tasks cheetah-run,walker-walk --sizes 1,8

The tasks (`SUBJECTS`) are those envpool 1.2.5 ships that issue 39 names: cheetah run,
walker walk, humanoid run, cartpole swingup, finger spin and quadruped run (`--tasks`
takes any registered suite task envpool also ships). The sides
(`bench.suite_sides`, which says what each runs): ours (`vector`, gym.make_vec's vector
entry point), the floor (mujoco.rollout of the same model, one call a round: physics
alone), `batch` (MuJoCo's batch stepped from Python, nothing read), and with `--against`,
envpool's DOMAINTASK-v1 and gymnasium's SyncVectorEnv of our single environments. Every
side runs in a process of its own (`bench.workers`); a side that has threads runs twice,
on 1 and on min(N, CPUs) threads (one process each), and is reported at the better of the
two (the count printed): threads cost CPU time where a call's work is short, and each
library's default differs (envpool's is min(N, CPUs), ours `composer.vector.threads`'
rule, whose pick is printed too). The rounds alternate between all the processes; a
round resets (not timed), then runs about 4096 environment steps (at most 800 control
steps, under the suite's 1,000-step episodes, so no round resets).

Figures: CPU time per environment step (the process', its threads included), best and
median round and the rounds' spread; throughput (environment steps per second of wall
time, best round), which follows the machine's load (the load average is noted before
and after each size). `<side>_vs_floor` is that side's throughput relative to the floor
(CPU figure, each at its better thread count): 1.0 is the floor's, higher is faster.
`vector_vs_<side>` is ours relative to that side's: above 1.0 we are faster;
`vector_default_vs_envpool` is ours at the thread count its default picks. Goals (issue
39): vector >= envpool at every N, and >= 0.95 of the floor at N >= 32. What the second
leaves: `room_us_a_call`, the CPU microseconds a call of N environment steps may spend
beyond MuJoCo's batch loop and stay within 0.95 of the floor ((floor / 0.95 - batch) x N;
below 0: the bare batch loop alone misses it), against `ours_over_batch_us_a_call`, what
ours spends beyond it ((vector - batch) x N: the step's Python, observations and reward).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

from bench import rounds, suite_sides
from bench.bench_vector import steps_per_round, usable_cpus
from bench.workers import Worker

SUBJECTS = (
    "cheetah-run", "walker-walk", "humanoid-run", "cartpole-swingup", "finger-spin",
    "quadruped-run",
)  # fmt: skip
SIZES = (1, 8, 32, 128)
AGAINST = ("envpool", "gymnasium")
BASE_SIDES = ("vector", "floor", "batch")
UNTHREADED = ("gymnasium",)  # sides that run on the calling thread alone
ROUNDS = 7
ENV_STEPS = 4096
QUICK_SUBJECTS = ("cartpole-swingup",)
FLOOR_GOAL = 0.95  # of the floor's throughput, at N >= 32 (issue 39)


def _figures(times: list[tuple[float, float]], env_steps: int) -> dict[str, float]:
    cpu = rounds.spread([c / env_steps * 1e6 for _, c in times])
    return {
        "cpu_us": cpu["best"], "cpu_us_median": cpu["median"], "cpu_spread": cpu["spread"],
        "steps_per_s": env_steps / min(w for w, _ in times),
    }  # fmt: skip


def _ratios(found: dict[str, dict[str, float]]) -> dict[str, float]:
    """Each side against the floor, ours against each side (CPU figures: see the module
    docstring), and ours against envpool in wall time too."""
    ratios = {}
    floor, ours = found.get("floor"), found.get("vector")
    for side, figures in found.items():
        if floor is not None and side != "floor":
            ratios[f"{side}_vs_floor"] = floor["cpu_us"] / figures["cpu_us"]
        if ours is not None and side != "vector":
            ratios[f"vector_vs_{side}"] = figures["cpu_us"] / ours["cpu_us"]
    if ours is not None and "envpool" in found:
        ratios["vector_vs_envpool_wall"] = ours["steps_per_s"] / found["envpool"]["steps_per_s"]
    return ratios


def _room(found: dict[str, dict[str, float]], num_envs: int) -> dict[str, float]:
    """The microseconds a call the floor goal leaves beyond the batch loop, and those ours
    spends beyond it (see the module docstring); empty without the three sides."""
    if not {"floor", "batch", "vector"} <= found.keys():
        return {}
    batch = found["batch"]["cpu_us"]
    return {
        "room_us_a_call": (found["floor"]["cpu_us"] / FLOOR_GOAL - batch) * num_envs,
        "ours_over_batch_us_a_call": (found["vector"]["cpu_us"] - batch) * num_envs,
    }


def _best(found: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:
    """Each side at its better thread count (the lower best CPU figure) from its runs
    `found` by label ('vector@2', 'gymnasium'), the count in 'threads'."""
    best: dict[str, dict[str, float]] = {}
    for label, figures in found.items():
        side, _, count = label.partition("@")
        entry = {**figures, "threads": float(count or 1)}
        if side not in best or entry["cpu_us"] < best[side]["cpu_us"]:
            best[side] = entry
    return best


def _load() -> float:
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")


def _print_size(num_envs: int, steps: int, found: dict[str, dict[str, float]]) -> None:
    print(f"  N = {num_envs} ({steps} control steps a round)")
    print(f"    {'side':12} {'CPU us/step':>11} {'median':>8} {'spread':>7} "
          f"{'steps/s (wall)':>15} {'vs floor':>9}")  # fmt: skip
    floor = min((f["cpu_us"] for label, f in found.items() if label.startswith("floor")),
                default=None)  # fmt: skip
    for label, f in found.items():
        relative = f"{floor / f['cpu_us']:9.2f}" if floor is not None else ""
        print(f"    {label:12} {f['cpu_us']:11.1f} {f['cpu_us_median']:8.1f} "
              f"{f['cpu_spread']:7.0%} {f['steps_per_s']:15.0f} {relative}")  # fmt: skip


def _print_summary(results: dict[str, Any], sizes: tuple[int, ...]) -> None:
    """One line per task and figure: ours against envpool and against the floor by N,
    and the thread counts each side was best at."""
    print("\nsummary (CPU time; ours / other as throughput: above 1 we are faster)")
    header = "".join(f"{f'N={n}':>8}" for n in sizes)
    for key in ("vector_vs_envpool", "vector_default_vs_envpool", "vector_vs_floor",
                "vector_vs_gymnasium", "envpool_vs_floor", "room_us_a_call",
                "ours_over_batch_us_a_call"):  # fmt: skip
        rows = [(s, r) for s, r in results["tasks"].items() if key in r.get(f"n{sizes[0]}", {})]
        if not rows:
            continue
        print(f"  {key:26}{header}")
        digits = 1 if key.endswith("_a_call") else 2
        for subject, found in rows:
            cells = "".join(f"{found[f'n{n}'][key]:8.{digits}f}" for n in sizes)
            print(f"    {subject:24}{cells}")
    print(f"  {'threads (best; ours default)':26}{header}")
    for subject, found in results["tasks"].items():
        for side in ("vector", "envpool", "floor"):
            if side not in found[f"n{sizes[0]}"]:
                continue
            cells = []
            for n in sizes:
                cell = f"{found[f'n{n}'][side]['threads']:.0f}"
                if side == "vector":
                    cell += f";{found[f'n{n}']['vector_default_threads']}"
                cells.append(f"{cell:>8}")
            print(f"    {subject + ' ' + side:24}" + "".join(cells))


def check_registered(subjects: tuple[str, ...]) -> None:
    """Raise ValueError naming the subjects whose dm_control/ ids are not registered."""
    import gymnasium

    import tasks  # noqa: F401  registers the dm_control/... ids

    unknown = [s for s in subjects if suite_sides.our_id(s) not in gymnasium.registry]
    if unknown:
        raise ValueError(
            f"unknown suite task(s) {unknown}: DOMAIN-TASK of a registered dm_control/ id, "
            "e.g. cheetah-run"
        )


def main(
    quick: bool = False,
    against: tuple[str, ...] = (),
    sizes: tuple[int, ...] = SIZES,
    subjects: tuple[str, ...] = (),
) -> dict[str, Any]:
    """Measure and print every task at every size; returns the figures and ratios by task
    and size ({'tasks': {'cheetah-run': {'n32': ...}}, ...}). `quick`: cartpole swingup
    (unless `subjects` are given) at N = 1 and 4, one round of a few steps. Raises
    ValueError for an unknown side in `against` or an unregistered subject."""
    unknown = set(against) - set(AGAINST)
    if unknown:
        raise ValueError(f"unknown side(s) {sorted(unknown)} to run against; known: {AGAINST}")
    if quick:
        sizes, round_count, env_steps = tuple(min(n, 4) for n in sizes[:2]), 1, 8
        subjects = subjects or QUICK_SUBJECTS
    else:
        round_count, env_steps = ROUNDS, ENV_STEPS
        subjects = subjects or SUBJECTS
    check_registered(subjects)
    cpus = usable_cpus()
    sides = list(BASE_SIDES)
    for side in against:
        how = suite_sides.missing(side)
        if how is None:
            sides.append(side)
        else:
            print(f"{side}: not installed, skipped; to compare with it: {how}")
    counts = sorted({1, min(cpus, max(sizes))})
    workers = {
        (side if side in UNTHREADED else f"{side}@{count}"): Worker("bench.suite_sides", side)
        for side in sides
        for count in ((1,) if side in UNTHREADED else counts)
    }
    results: dict[str, Any] = {"cpus": cpus, "sides": {}, "tasks": {}}
    try:
        print(f"{cpus} CPUs usable; each side with threads on 1 and min(N, {cpus}) threads, "
              "reported at the better")  # fmt: skip
        for side in sides:
            label = next(label for label in workers if label.partition("@")[0] == side)
            results["sides"][side] = workers[label].describe()
            print(f"  {side:10} {results['sides'][side]}")
        for subject in subjects:
            print(f"\n{subject} ({suite_sides.our_id(subject)}, envpool "
                  f"{suite_sides.envpool_id(subject)})")  # fmt: skip
            task_results: dict[str, Any] = {}
            for num_envs in sizes:
                steps = steps_per_round(num_envs, env_steps)
                running = {}
                default_threads = None
                for label, worker in workers.items():
                    count = int(label.partition("@")[2] or 1)
                    if count != 1 and count > min(cpus, num_envs):
                        worker.drop()  # one thread count at N = 1
                        continue
                    picked = worker.build(num_envs, count, subject)
                    if default_threads is None:
                        default_threads = picked
                    running[label] = worker
                load_before = _load()
                timed = rounds.alternate(
                    {label: (lambda w=w, s=steps: w.round(s)) for label, w in running.items()},
                    round_count,
                )
                load = (load_before, _load())
                found = {label: _figures(t, steps * num_envs) for label, t in timed.items()}
                _print_size(num_envs, steps, found)
                best = _best(found)
                ratios = {**_ratios(best), **_room(best, num_envs)}
                default = found.get(f"vector@{default_threads}")
                if default is not None and "envpool" in best:
                    ratios["vector_default_vs_envpool"] = (
                        best["envpool"]["cpu_us"] / default["cpu_us"]
                    )
                listed = ", ".join(f"{key} {value:.2f}" for key, value in ratios.items())
                chosen = ", ".join(f"{side} {f['threads']:.0f}" for side, f in best.items())
                print(f"    load {load[0]:.1f} -> {load[1]:.1f}; threads: {chosen} (ours' "
                      f"default {default_threads}); {listed}")  # fmt: skip
                task_results[f"n{num_envs}"] = {
                    **best, **ratios, "runs": found, "load": load,
                    "vector_default_threads": default_threads,
                }  # fmt: skip
            results["tasks"][subject] = task_results
    finally:
        for worker in workers.values():
            worker.close()
    _print_summary(results, sizes)
    return results


def _command_line(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", default="", help=f"comma-separated: {', '.join(AGAINST)}")
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)), help="numbers of envs")
    parser.add_argument("--tasks", default=",".join(SUBJECTS), help="DOMAIN-TASK, comma-separated")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    return {
        "quick": args.quick,
        "against": tuple(filter(None, args.against.split(","))),
        "sizes": tuple(int(n) for n in args.sizes.split(",")),
        "subjects": tuple(filter(None, args.tasks.split(","))),
    }


if __name__ == "__main__":
    main(**_command_line())
