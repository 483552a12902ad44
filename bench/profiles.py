"""Where the microseconds of one operation go: py-spy's samples scaled by measured CPU time.

    python -m bench.profiles step CartpoleSwingup     # one Environment.step via gym.make
    python -m bench.profiles reset AntRun             # one reset via gym.make
    python -m bench.profiles vector 8                 # one VectorEnvironment.step, 8 ants
                                                      # (on one thread: see _vector)
    python -m bench.profiles suite cheetah-run:32     # one step of gym.make_vec's vector
                                                      # of 32 suite environments (one thread)
    python -m bench.profiles parse rodent             # one mjcf.from_path (bench.real_models)
    python -m bench.profiles step Reach --lines 20    # ... and the 20 costliest lines
    python -m bench.profiles step Reach --cprofile    # cProfile instead of py-spy

A child process times the operation (CPU time per call, the median of 5 stretches), and
another repeats it while `py-spy record --native` samples it (`pip install py-spy`: the
[bench] extra).
Each sample is charged to the innermost Python function on its stack (MuJoCo's and
numpy's C code to the Python line that called it; the MuJoCo share is shown apart; the
cyclic garbage collector, which runs wherever an allocation triggers it, to
'(garbage collector)'), and
the shares are scaled by the CPU time per call: microseconds per call of each function
(self, with what it calls in C), of each function of ours including what it calls
(inclusive), and of each line of ours including what it calls (numpy, MuJoCo ...).
Resets at episode ends are left out of step profiles.
cProfile's figures (--cprofile) count Python calls exactly but inflate small functions.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pstats
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
OURS = ("composer/", "mjcf/", "tasks/", "entities/", "arenas/", "bench/")
_PYTHON_FRAME = re.compile(r"^(?P<function>.+) \((?P<file>.+\.py):(?P<line>\d+)\)$")
_SAMPLED = "_sampled_loop"
_LEFT_OUT = "_left_out"  # frames under it (episode resets) are not the operation's
_COLLECTOR = "gc_collect"  # CPython's cyclic garbage collector (native frames)
GARBAGE = "(garbage collector)"


def _step(name: str) -> Callable[[], None]:
    from bench import bench_task_step

    env, _, _ = bench_task_step.make(name)
    env.reset(seed=0)
    action = env.action_space.sample()

    def step() -> None:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            _left_out(env.reset)

    return step


def _reset(name: str) -> Callable[[], None]:
    from bench import bench_task_step

    env, _, _ = bench_task_step.make(name)
    env.reset(seed=0)
    return env.reset


def _vector(num_envs: str) -> Callable[[], None]:
    import composer
    from bench.ant_v5 import AntV5
    from bench.vector_sides import actions

    # One thread: py-spy samples Python threads only, and the time per call is then all
    # the sampled thread's (MuJoCo's pool threads would add CPU time it never sees).
    env = composer.VectorEnvironment(AntV5, int(num_envs), nthread=1)
    env.reset(seed=0)
    chosen = actions(int(num_envs))[0]
    return lambda: env.step(chosen)


def _suite(subject: str) -> Callable[[], None]:
    import gymnasium

    import tasks  # noqa: F401  registers the suite's ids

    name, _, count = subject.partition(":")
    num_envs = int(count or 1)
    env = gymnasium.make_vec(
        f"dm_control/{name}-v0", num_envs, vectorization_mode="vector_entry_point", nthread=1
    )  # one thread, as _vector
    env.reset(seed=0)
    space = env.single_action_space
    chosen = np.random.default_rng(0).uniform(space.low, space.high, (num_envs, *space.shape))
    step, steps = env.step, [0]

    def operation() -> None:
        step(chosen)
        steps[0] += 1
        if steps[0] % 900 == 0:  # before the episodes' 1,000-step limit: no autoresets
            _left_out(lambda: env.reset(seed=0))

    return operation


def _parse(name: str) -> Callable[[], None]:
    import mjcf
    from bench import real_models

    path = real_models.files(name)[0][name]
    return lambda: mjcf.from_path(path)


WORKLOADS: dict[str, Callable[[str], Callable[[], None]]] = {
    "step": _step, "reset": _reset, "vector": _vector, "suite": _suite, "parse": _parse,
}  # fmt: skip


def _left_out(function: Callable[[], object]) -> None:
    function()


def _timed_loop(operation: Callable[[], None], seconds: float) -> float:
    """CPU microseconds per call: the median of 5 stretches of `seconds` / 5."""
    per_call = []
    for _ in range(5):
        calls, start, deadline = 0, time.process_time(), time.perf_counter() + seconds / 5
        while time.perf_counter() < deadline:
            operation()
            calls += 1
        per_call.append((time.process_time() - start) / calls * 1e6)
    return sorted(per_call)[2]


def _sampled_loop(operation: Callable[[], None], seconds: float) -> None:
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline:
        operation()


def child(workload: str, argument: str, seconds: float, out: Path | None) -> None:
    """Build the workload and warm it (caches, first calls); then time it and write the
    CPU microseconds per call to `out` (JSON), or with no `out`, run it for `seconds` to
    be sampled."""
    operation = WORKLOADS[workload](argument)
    _timed_loop(operation, min(1.0, seconds / 4))
    if out is not None:
        out.write_text(json.dumps({"us_per_call": _timed_loop(operation, seconds / 2)}))
    else:
        _sampled_loop(operation, seconds)


def _frames(stack: str) -> list[tuple[str, str, int] | str]:
    """A raw py-spy stack, root first: (function, file, line) for Python frames, the
    frame's text for native ones."""
    found: list[tuple[str, str, int] | str] = []
    for frame in stack.split(";"):
        match = _PYTHON_FRAME.match(frame)
        found.append((match["function"], match["file"], int(match["line"])) if match else frame)
    return found


def charge(raw: str) -> dict[str, Counter]:
    """Samples of the sampled loop, by innermost Python function ('self'), by innermost
    line of ours, with all it calls ('lines'), by function of ours anywhere on the stack
    ('inclusive'), and those whose innermost frame is MuJoCo's C code by that Python
    function ('mujoco'); 'total' counts the samples."""
    found = {key: Counter() for key in ("self", "lines", "inclusive", "mujoco", "total")}
    for line in raw.splitlines():
        stack, _, count_text = line.rpartition(" ")
        if _SAMPLED not in stack or _LEFT_OUT in stack:
            continue
        count = int(count_text)
        frames = _frames(stack)
        start = max(i for i, f in enumerate(frames) if isinstance(f, tuple) and f[0] == _SAMPLED)
        frames = frames[start + 1 :]
        python = [f for f in frames if isinstance(f, tuple)]
        found["total"]["all"] += count
        if not python:
            continue
        function, file, _ = python[-1]
        own = [f for f in python if f[1].startswith(OURS)]
        if any(isinstance(f, str) and f.startswith(_COLLECTOR) for f in frames):
            found["self"][GARBAGE] += count
            found["lines"][GARBAGE] += count
        else:
            found["self"][f"{file}:{function}"] += count
            if own:
                found["lines"][f"{own[-1][1]}:{own[-1][2]} ({own[-1][0]})"] += count
        if isinstance(frames[-1], str) and "mujoco" in frames[-1].lower():
            found["mujoco"][f"{file}:{function}"] += count
        for key in {f"{f[1]}:{f[0]}" for f in python if f[1].startswith(OURS)}:
            found["inclusive"][key] += count
    return found


def report(found: dict[str, Counter], us_per_call: float, top: int, lines: int) -> None:
    """Print the charged samples as microseconds per call (see the module docstring)."""
    total = found["total"]["all"] or 1
    scale = us_per_call / total
    shown = {
        "self (innermost Python function, with the C it calls)": found["self"].most_common(top),
        "inclusive (our functions and all they call)": found["inclusive"].most_common(top),
        "lines of ours (with all they call)": found["lines"].most_common(lines),
    }
    width = max(len(key) for rows in shown.values() for key, _ in rows)
    print(f"{us_per_call:.1f} us CPU per call; {total} samples")
    for title, rows in shown.items():
        if not rows:
            continue
        mujoco = title.startswith("self")
        print(f"\n  {title:{width}} {'us':>7}" + (f" {'MuJoCo C':>8}" if mujoco else ""))
        for key, count in rows:
            extra = f" {found['mujoco'][key] * scale:8.1f}" if mujoco else ""
            print(f"  {key:{width}} {count * scale:7.1f}{extra}")


def _py_spy(workload: str, argument: str, seconds: float, rate: int, native: bool) -> tuple:
    spy = shutil.which("py-spy")
    if spy is None:
        raise SystemExit("py-spy is not installed: pip install -e '.[bench]' (or use --cprofile)")
    with tempfile.TemporaryDirectory() as folder:
        raw, timing = Path(folder) / "raw.txt", Path(folder) / "timing.json"
        this = [sys.executable, "-m", "bench.profiles", workload, argument, "--seconds",
                str(seconds), "--child"]  # fmt: skip
        subprocess.run([*this, str(timing)], check=True, cwd=REPO, capture_output=True)
        command = [spy, "record", "-r", str(rate), "-f", "raw", "-o", str(raw)]
        command += ["--native"] if native else []
        subprocess.run([*command, "--", *this, ""], check=True, cwd=REPO, capture_output=True)
        return raw.read_text(), json.loads(timing.read_text())["us_per_call"]


def _cprofile(workload: str, argument: str, seconds: float, top: int) -> None:
    operation = WORKLOADS[workload](argument)
    _timed_loop(operation, min(1.0, seconds / 4))
    profiler, calls = cProfile.Profile(), 0
    deadline = time.perf_counter() + seconds
    profiler.enable()
    while time.perf_counter() < deadline:
        operation()
        calls += 1
    profiler.disable()
    stats = pstats.Stats(profiler)
    print(f"{calls} calls under cProfile; per call, by own time:")
    rows = sorted(stats.stats.items(), key=lambda item: -item[1][2])[:top]  # type: ignore[attr-defined]
    for (file, line, function), (_, ncalls, tottime, cumtime, _) in rows:
        where = f"{os.path.relpath(file, REPO) if file.startswith('/') else file}:{line}"
        print(
            f"  {where + ' ' + function:70} {ncalls / calls:6.1f} calls "
            f"{tottime / calls * 1e6:7.1f} us own {cumtime / calls * 1e6:7.1f} us cum"
        )


def main(argv: list[str] | None = None) -> None:
    """The command line (see the module docstring)."""
    parser = argparse.ArgumentParser(
        prog="python -m bench.profiles", description=__doc__.splitlines()[0]
    )
    parser.add_argument("workload", choices=sorted(WORKLOADS))
    parser.add_argument("argument", help="task or gymnasium id, number of envs, or model name")
    parser.add_argument("--seconds", type=float, default=8.0, help="sampled for this long")
    parser.add_argument("--rate", type=int, default=1000, help="samples per second")
    parser.add_argument("--top", type=int, default=25)
    parser.add_argument("--lines", type=int, default=0, help="also the N costliest lines")
    parser.add_argument("--no-native", action="store_true", help="no C frames (faster)")
    parser.add_argument("--cprofile", action="store_true")
    parser.add_argument("--raw", type=Path, help="also keep py-spy's raw samples here")
    parser.add_argument("--child", help=argparse.SUPPRESS)  # a file to time into, or ''
    args = parser.parse_args(argv)
    if args.child is not None:
        child(args.workload, args.argument, args.seconds, Path(args.child) if args.child else None)
    elif args.cprofile:
        _cprofile(args.workload, args.argument, args.seconds, args.top)
    else:
        raw, us = _py_spy(args.workload, args.argument, args.seconds, args.rate, not args.no_native)
        if args.raw is not None:
            args.raw.write_text(raw)
        print(f"{args.workload} {args.argument}: ", end="")
        report(charge(raw), us, args.top, args.lines)


if __name__ == "__main__":
    main()
