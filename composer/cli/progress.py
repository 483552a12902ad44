"""The progress bar of `composer train`, one for both engines: the run's steps done of its
total (a resumed run's earlier steps counted), on a terminal only.

    bar = progress.Bar.open(total=100_000, done=20_480)    # None where stderr is no terminal
    bar.advance_to(24_576)                                  # the run's steps now
    progress.say(bar, "   24,576 steps  12s  return 41.02")  # a line above the bar
    bar.close()
    20,480/100,000 steps  20% |████▏               | 0:12<0:47, 341 steps/s

The last update of a run passes its total when the algorithm collects whole rollouts (PPO
collects n_steps x environments at a time): the total then grows to the steps done, so the
bar ends full, at the true count ("102,400/102,400", never "102,400/99,280").
"""

from __future__ import annotations

import sys
from typing import IO

from tqdm import tqdm

FORMAT = "{n:,}/{total:,} steps {percentage:3.0f}% |{bar}| {elapsed}<{remaining}, {rate_fmt}"


class Bar:
    """A tqdm bar of the run's steps (see the module docstring)."""

    def __init__(self, total: int, done: int, file: IO[str] | None = None) -> None:
        """A bar at `done` of `total` steps, drawn on `file` (default: stderr)."""
        self._bar = tqdm(
            total=max(total, done), initial=done, unit=" steps", bar_format=FORMAT,
            file=file if file is not None else sys.stderr, dynamic_ncols=True,
        )  # fmt: skip

    @classmethod
    def open(cls, total: int, done: int) -> Bar | None:
        """A Bar on stderr when it is a terminal, else None (logs get the report lines)."""
        return cls(total, done) if sys.stderr.isatty() else None

    def advance_to(self, timesteps: int) -> None:
        """Show `timesteps` done (the total grows to them if they pass it)."""
        bar = self._bar
        if timesteps > bar.total:
            bar.total = timesteps
        bar.update(timesteps - bar.n)

    def write(self, line: str) -> None:
        """Print `line` on stdout, above the bar."""
        tqdm.write(line)

    def close(self) -> None:
        """Leave the bar as it is, and the cursor below it."""
        self._bar.close()


def say(bar: Bar | None, line: str) -> None:
    """Print `line`: above `bar` if there is one, else on stdout."""
    if bar is None:
        print(line, flush=True)
    else:
        bar.write(line)
