"""The `composer` command-line tool: list, show, run, train and evaluate tasks.

    $ composer list                            # or: python -m composer list
    $ composer show Reach                      # the scene, and Reach.png
    $ composer run Reach --video reach.mp4     # a random policy, recorded
    $ composer train                           # Reach, about ten minutes on a laptop CPU
    $ composer eval Reach runs/Reach-ppo

From Python: `composer.cli.main(['list'])` returns the exit status. `train` and `eval` (and
`run --policy PATH`) need the `[train]` extra: stable-baselines3 and torch; the rest need
only the base install (`run --video` also needs imageio). Modules: `main` (arguments and
errors), one per command (`listing`, `show`, `run`, `train`, `evaluate`), `catalog`
(registered tasks), `rollout` (episodes), `video`, `plot`, `recipes` (the hyperparameter
table) and `training` (stable-baselines3: environments, checkpoints, sessions).
"""

from composer.cli.main import main

__all__ = ["main"]
