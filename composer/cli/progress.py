"""The progress bar of `composer train`, one for both engines: the run's steps done of its
total (a resumed run's earlier steps counted), the time it has left with its evaluations
counted, on a terminal only.

    bar = progress.Bar.open(total=100_352, done=20_480, evaluations=8)  # None: no terminal
    bar.advance_to(24_576)                                  # the run's steps now
    with progress.evaluating(bar):                          # an evaluation (bar may be None)
        ...
    progress.say(bar, "   24,576 steps  12s  return 41.02")  # a line above the bar
    bar.close()
"""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Callable, Iterator
from typing import IO, Any

from tqdm import tqdm

FORMAT = "{n:,}/{total:,} steps {percentage:3.0f}% |{bar}| {elapsed}<{left}, {speed}"


class Estimate:
    """How long a run has left, from the durations it is told.

    The time left is the steps left at the speed training has run in this session,
    the time spent evaluating taken out, plus the evaluations still due at the time the last
    one took; until one has been timed it says how many are to come ('02:40 + 8 evaluations').
    The speed is that of training alone, so an evaluation neither stalls it nor makes it jump.
    The final evaluation after training, the random policy's episodes and the video come after
    the bar (the announcement says so).
    """

    def __init__(self, total: int, done: int, evaluations: int) -> None:
        """A run at `done` of `total` steps with `evaluations` still due before its end."""
        self.total = total
        self.steps = done
        self.evaluations_left = evaluations
        self._first = done
        self._training_seconds = 0.0
        self._last_evaluation: float | None = None

    def trained(self, steps: int, seconds: float) -> None:
        """The run is at `steps` after `seconds` more of training."""
        self.steps = steps
        self._training_seconds += seconds

    def evaluated(self, seconds: float) -> None:
        """An evaluation took `seconds`."""
        self.evaluations_left = max(0, self.evaluations_left - 1)
        self._last_evaluation = seconds

    def speed(self) -> float | None:
        """Steps per second of training in this session, evaluations left out; None before
        any step."""
        trained = self.steps - self._first
        if trained <= 0 or self._training_seconds <= 0:
            return None
        return trained / self._training_seconds

    def seconds_left(self) -> float | None:
        """Seconds to the end of training, evaluations included; None until the speed and an
        evaluation's time (where evaluations are left) are known."""
        speed = self.speed()
        if speed is None or (self.evaluations_left and self._last_evaluation is None):
            return None
        training = max(0, self.total - self.steps) / speed
        return training + self.evaluations_left * (self._last_evaluation or 0.0)

    def text(self) -> str:
        """The time left as the bar shows it: '03:47', '02:40 + 8 evaluations' before
        one was timed, '?' before training's speed is known."""
        speed = self.speed()
        if speed is None:
            return "?"
        left = self.seconds_left()
        if left is not None:
            return tqdm.format_interval(left)
        training = tqdm.format_interval(max(0, self.total - self.steps) / speed)
        plural = "s" if self.evaluations_left != 1 else ""
        return f"{training} + {self.evaluations_left} evaluation{plural}"

    def speed_text(self) -> str:
        """'341 steps/s', or '? steps/s' before any step."""
        speed = self.speed()
        return "? steps/s" if speed is None else f"{speed:,.0f} steps/s"


class _Meter(tqdm):
    """tqdm drawing `Estimate`'s time left and speed (FORMAT's `left` and `speed`)."""

    def __init__(self, estimate: Estimate, **kwargs: Any) -> None:
        self.estimate = estimate
        super().__init__(**kwargs)

    @property
    def format_dict(self) -> dict[str, Any]:
        values = dict(super().format_dict)
        values["left"] = self.estimate.text()
        values["speed"] = self.estimate.speed_text()
        return values


class Bar:
    """A tqdm bar of the run's steps:

        24,576/100,352 steps  24% |████▉               | 00:12<03:47, 341 steps/s

    The total is where the run will end (`composer.cli.engines.base.Collection.end`): an
    algorithm that collects whole rollouts ends past `--timesteps`, and the bar says so from
    its first line. Should the steps pass the total all the same, the total grows to them, so
    the bar ends full, at the true count ("102,400/102,400", never "102,400/99,280").
    """

    def __init__(
        self,
        total: int,
        done: int,
        evaluations: int = 0,
        file: IO[str] | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        """A bar at `done` of `total` steps with `evaluations` due before the end, drawn
        on `file` (default: stderr), timing with `clock` (seconds)."""
        self.estimate = Estimate(max(total, done), done, evaluations)
        self._clock = clock
        self._bar = _Meter(
            self.estimate, total=max(total, done), initial=done, unit=" steps",
            bar_format=FORMAT, file=file if file is not None else sys.stderr,
            dynamic_ncols=True,
        )  # fmt: skip
        self._mark = clock()

    @classmethod
    def open(cls, total: int, done: int, evaluations: int = 0) -> Bar | None:
        """A Bar on stderr when it is a terminal, else None (logs get the report lines)."""
        return cls(total, done, evaluations) if sys.stderr.isatty() else None

    def advance_to(self, timesteps: int) -> None:
        """Show `timesteps` done (the total grows to them if they pass it)."""
        now = self._clock()
        self.estimate.trained(timesteps, now - self._mark)
        self._mark = now
        bar = self._bar
        if timesteps > bar.total:
            bar.total = self.estimate.total = timesteps
        bar.update(timesteps - bar.n)

    @contextlib.contextmanager
    def evaluating(self) -> Iterator[None]:
        """Within `with`: an evaluation, timed for the estimate and left out of the speed."""
        start = self._clock()
        self.estimate.trained(self.estimate.steps, start - self._mark)
        try:
            yield
        finally:
            self._mark = self._clock()
            self.estimate.evaluated(self._mark - start)
            self._bar.refresh()

    def write(self, line: str) -> None:
        """Print `line` on stdout, above the bar."""
        tqdm.write(line)

    def close(self) -> None:
        """Leave the bar as it is, and the cursor below it."""
        self._bar.close()


def evaluating(bar: Bar | None) -> contextlib.AbstractContextManager[None]:
    """`bar.evaluating()`, or nothing to time without a bar."""
    return contextlib.nullcontext() if bar is None else bar.evaluating()


def say(bar: Bar | None, line: str) -> None:
    """Print `line`: above `bar` if there is one, else on stdout."""
    if bar is None:
        print(line, flush=True)
    else:
        bar.write(line)
