"""Alternating rounds and what is reported of them, shared by the benchmarks.

    times = alternate({'ours': run_ours, 'mujoco': run_mujoco}, rounds=7)
    spread(times['ours'])        # {'best': ..., 'median': ..., 'spread': ...}

On a machine shared with other work, one side measured after the other would take the
load of that moment: rounds alternate between the sides instead, so that a busy spell
hits them alike, and each side's figure is a statistic of its own rounds. CPU time (of
the process or thread) is the robust figure: time that other processes take from this
one is not counted; it still grows a little with the load (caches, frequency).
"""

from __future__ import annotations

import statistics
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def alternate(sides: dict[str, Callable[[], T]], rounds: int) -> dict[str, list[T]]:
    """Run each side's round in turn, `rounds` times, each round starting one side further
    along (no side always runs just after the same other); what each side's rounds
    returned, in order."""
    found: dict[str, list[T]] = {name: [] for name in sides}
    names = list(sides)
    for round_number in range(rounds):
        start = round_number % len(names)
        for name in names[start:] + names[:start]:
            found[name].append(sides[name]())
    return found


def spread(values: list[float]) -> dict[str, float]:
    """The best (lowest) and median of `values`, and their spread: the interquartile range
    over the median, how much the middle half of the rounds disagreed (a pause of the
    process in one round does not count)."""
    median = statistics.median(values)
    quartiles = statistics.quantiles(values, n=4) if len(values) > 1 else [median] * 3
    return {
        "best": min(values),
        "median": median,
        "spread": (quartiles[2] - quartiles[0]) / median if median else 0.0,
    }
