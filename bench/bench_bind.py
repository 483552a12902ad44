"""Cost of a bound read and write per call, next to raw numpy indexing of MjData, same run.

    python bench/bench_bind.py            # gymnasium's humanoid

Prints ns per call and the ratio to the raw equivalent, for one element and for lists:
`binding.qpos` against `data.qpos[a:b]` (one joint, or joints whose rows are one contiguous
run: a view) and against `data.qpos[idx]` (joints whose rows are scattered: a fancy index);
a derived field (`xpos`, which a binding first checks is up to date) against `data.xpos[i]`
and `data.xpos[idx]`; writes likewise (a binding's write also marks the physics dirty). The
target is a ratio within 1.5x. Bound and raw calls are timed in alternating rounds and each
figure is the best round of process CPU time, so that noise from other processes hits both
sides alike.
"""

from __future__ import annotations

import os
import sys
import time
import timeit
from pathlib import Path

import gymnasium
import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

from mjcf.sim.physics import Physics

ROUNDS = 40
NUMBER = 20_000


def best_ns(bound, raw, rounds: int = ROUNDS, number: int = NUMBER) -> tuple[float, float]:
    """Best per-call times (ns) of `bound` and `raw`, timed in alternating rounds."""
    best_bound = best_raw = float("inf")
    for _ in range(rounds):
        best_bound = min(best_bound, timeit.Timer(bound, timer=time.process_time).timeit(number))
        best_raw = min(best_raw, timeit.Timer(raw, timer=time.process_time).timeit(number))
    return best_bound / number * 1e9, best_raw / number * 1e9


def main(quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure and print; returns ns per call and the ratio for each case. `quick`: a
    tiny budget (for checking the plumbing, not the numbers)."""
    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs/mujoco/assets/humanoid.xml")
    physics = Physics.from_xml_path(path)
    model, data = physics.model, physics.data
    joint, body = mujoco.mjtObj.mjOBJ_JOINT, mujoco.mjtObj.mjOBJ_BODY

    # Irregularly scattered joints: no slice covers their qpos rows, so reads are copies
    # (fancy indexing) that write back on item assignment.
    scattered = np.array([1, 2, 5, 6, 9, 13, 14, 17])
    fancy = physics._binding(joint, scattered)
    idx = model.jnt_qposadr[scattered].astype(np.intp)
    # Consecutive joints: one run of rows, so reads are views.
    run = np.arange(1, 8)
    contiguous = physics._binding(joint, run)
    lo, hi = int(model.jnt_qposadr[run[0]]), int(model.jnt_qposadr[run[-1]]) + 1
    values = np.linspace(-0.1, 0.1, idx.size)
    run_values = np.linspace(-0.1, 0.1, hi - lo)
    one = physics._binding(joint, 5)
    at = int(model.jnt_qposadr[5])
    torso = physics._binding(body, 1)
    bodies_ids = np.array([1, 4, 7, 2])
    bodies = physics._binding(body, bodies_ids)

    assert np.array_equal(fancy.qpos, data.qpos[idx])
    assert np.array_equal(contiguous.qpos, data.qpos[lo:hi])
    assert np.array_equal(bodies.xpos, data.xpos[bodies_ids])

    def raw_write_fancy() -> None:
        data.qpos[idx] = values

    def bind_write_fancy() -> None:
        fancy.qpos = values

    def raw_write_slice() -> None:
        data.qpos[lo:hi] = run_values

    def bind_write_slice() -> None:
        contiguous.qpos = run_values

    def raw_write_one() -> None:
        data.qpos[at : at + 1] = 0.1

    def bind_write_one() -> None:
        one.qpos = 0.1

    rows = [
        ("read, one joint", lambda: one.qpos, lambda: data.qpos[at : at + 1]),
        ("read, scattered rows", lambda: fancy.qpos, lambda: data.qpos[idx]),
        ("read, contiguous rows", lambda: contiguous.qpos, lambda: data.qpos[lo:hi]),
        ("read derived, one body", lambda: torso.xpos, lambda: data.xpos[1]),
        ("read derived, 4 bodies", lambda: bodies.xpos, lambda: data.xpos[bodies_ids]),
        ("write, one joint", bind_write_one, raw_write_one),
        ("write, scattered rows", bind_write_fancy, raw_write_fancy),
        ("write, contiguous rows", bind_write_slice, raw_write_slice),
    ]
    print(f"humanoid: nq={model.nq}; {idx.size} scattered joints, {run.size} contiguous joints")
    print(f"{'case':<26}{'bind ns':>10}{'raw ns':>10}{'ratio':>8}")
    results = {}
    for name, bound, raw in rows:
        physics.forward()  # writes leave the physics dirty: start each case clean
        b, r = best_ns(bound, raw, *((2, 100) if quick else (ROUNDS, NUMBER)))
        print(f"{name:<26}{b:>10.0f}{r:>10.0f}{b / r:>8.2f}")
        results[name] = {"bind_ns": b, "raw_ns": r, "bind_vs_raw": b / r}
    return results


if __name__ == "__main__":
    main()
