"""How results read: a summary in full (`run`, `eval`, the end of `train`) and the same
measures as short columns under `train`'s progress bar, from one formatter."""

from __future__ import annotations

import pytest

from composer.cli import describe, rollout

REACH = [rollout.Episode(12.0, 75, True), rollout.Episode(10.0, 75, False)]
RUNNER = [rollout.Episode(50.0, 500, None, 1.25), rollout.Episode(40.0, 500, None, 1.0)]


@pytest.mark.parametrize(
    ("episodes", "full", "short"),
    [
        (REACH, "return 11.00 ± 1.00 over 2 episodes, success rate 0.50",
         "return 11.00 ± 1.00  success 0.50"),
        (RUNNER, "return 45.00 ± 5.00 over 2 episodes, forward speed 1.12 m/s",
         "return 45.00 ± 5.00  1.12 m/s"),
        (REACH[:1], "return 12.00 ± 0.00 over 1 episode, success rate 1.00",
         "return 12.00 ± 0.00  success 1.00"),
    ],
)  # fmt: skip
def test_a_summary_reads_in_full_and_as_columns(episodes, full, short):
    stats = rollout.summary(episodes)
    assert describe.summary(stats) == full
    assert describe.summary(stats, compact=True) == short
    result = {"timesteps": 200_000, "wall_time": 92.4, **stats}
    assert describe.evaluation(result) == f"   200,000 steps  1m32s  {short}"
    assert len(describe.evaluation({**result, "timesteps": 99_999_999})) <= 80


def test_episodes_durations_and_counts():
    assert describe.episode(REACH[1]) == "return 10.00 over 75 steps, no success"
    assert describe.episode(RUNNER[0]) == "return 50.00 over 500 steps, 1.25 m/s"
    assert [describe.duration(s) for s in (42.4, 185, 3725)] == ["42s", "3m05s", "1h02m"]
    assert describe.count(1, "environment") == "1 environment"
    assert describe.count(16, "env runner") == "16 env runners"
