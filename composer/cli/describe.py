"""Results in words: how `run`, `eval`, `view` and `train` write an episode, a summary of
episodes and an evaluation during training (one formatter of the measures for both), a
duration and a count.

    describe.episode(episode)        # 'return 16.15 over 75 steps, no success'
    describe.summary(stats)          # 'return 59.03 ± 8.92 over 100 episodes, success rate 0.98'
    describe.evaluation(result)      # '   200,000 steps  1m32s  return 44.38 ± 14.73  success 0.50'
    describe.duration(92)            # '1m32s'
    describe.count(16, 'environment')   # '16 environments'
"""

from __future__ import annotations

from typing import Any

from composer.cli.rollout import Episode

# The measures after the return: (key, written in full, written short), two decimals each.
_MEASURES = (
    ("success_rate", "success rate {:.2f}", "success {:.2f}"),
    ("forward_speed", "forward speed {:.2f} m/s", "{:.2f} m/s"),
)


def episode(episode: Episode) -> str:
    """'return 12.30 over 250 steps, success, 1.20 m/s' (success and speed where the task
    reports them)."""
    text = f"return {episode.episode_return:.2f} over {episode.length} steps"
    if episode.success is not None:
        text += ", success" if episode.success else ", no success"
    if episode.forward_speed is not None:
        text += f", {episode.forward_speed:.2f} m/s"
    return text


def summary(stats: dict[str, Any], compact: bool = False) -> str:
    """'return 12.30 ± 4.50 over 10 episodes, success rate 0.90, forward speed 1.20 m/s';
    `compact`: 'return 12.30 ± 4.50  success 0.90  1.20 m/s' (no episode count). `stats`
    (`rollout.summary`) holds the mean and spread of the returns, then the success rate and
    the forward speed of the tasks that report them (None for the others)."""
    text = f"return {stats['mean_return']:.2f} ± {stats['std_return']:.2f}"
    if not compact:
        text += f" over {count(stats['episodes'], 'episode')}"
    for key, full, short in _MEASURES:
        if stats.get(key) is not None:
            text += ("  " + short if compact else ", " + full).format(stats[key])
    return text


def evaluation(result: dict[str, Any]) -> str:
    """An evaluation during training (a summary with 'timesteps' and 'wall_time'):
    '   200,000 steps  1m32s  return 44.38 ± 14.73  success 0.50', in short columns, for a
    line under the progress bar of `composer train` that fits an 80-column terminal."""
    when = f"{result['timesteps']:>10,} steps {duration(result['wall_time']):>6}"
    return f"{when}  {summary(result, compact=True)}"


def duration(seconds: float) -> str:
    """'42s', '3m05s', '1h02m'."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"


def count(number: int, noun: str) -> str:
    """'1 environment', '16 environments'."""
    return f"{number} {noun}{'s' if number != 1 else ''}"
