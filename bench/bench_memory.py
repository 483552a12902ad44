"""Memory over a long run: RSS while an environment steps a million times with resets.

    python bench/bench_memory.py [steps]        # default 1_000_000

Prints the resident set size every 10% of the run; a flat line is the promise. The
test suite checks the same for Python allocations over a shorter run
(tests/reliability/test_long_runs.py).
"""

from __future__ import annotations

import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import gymnasium as gym

import tasks  # noqa: F401 - registers the composer/* ids


def rss_megabytes() -> float:
    """Current resident set size of this process in MiB (Linux)."""
    with open("/proc/self/statm") as handle:
        pages = int(handle.read().split()[1])
    return pages * resource.getpagesize() / 2**20


def main(steps: int = 1_000_000) -> dict[str, float]:
    """Step CartpoleSwingup `steps` times (episodes of 2 s); print RSS as it goes."""
    env = gym.make("composer/CartpoleSwingup-v0", flatten_observations=True, time_limit=2.0)
    env.reset(seed=0)
    start = time.perf_counter()
    samples = []
    for step in range(1, steps + 1):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()
        if step % max(1, steps // 10) == 0:
            samples.append(rss_megabytes())
            print(
                f"{step:>9} steps  {time.perf_counter() - start:7.1f} s  RSS {samples[-1]:7.1f} MiB"
            )
    growth = samples[-1] - samples[0]
    print(f"RSS growth after the first tenth: {growth:+.1f} MiB")
    return {"rss_growth_mib": growth, "steps": steps}


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
