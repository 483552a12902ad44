"""The `composer` command-line tool: list, show, run, view, train and evaluate tasks.

    $ composer list                            # or: python -m composer list
    $ composer show Reach --out reach.png      # the scene, and a frame of it
    $ composer run Reach --video reach.mp4     # a random policy, recorded
    $ composer view AntRun                     # MuJoCo's interactive viewer
    $ composer train                           # Reach, about five minutes on a laptop CPU
    $ composer eval Reach runs/Reach-ppo

From Python: `composer.cli.main(['list'])` returns the exit status. `train` and `eval` (and
`--policy PATH` of `run` and `view`) need the `[train]` extra: stable-baselines3 and torch;
the rest need only the base install (`run --video` also needs imageio). Modules: `main`
(arguments and errors), one per command (`listing`, `show`, `run`, `view`, `train`,
`evaluate`), `catalog` (registered tasks), `rollout` (episodes), `video`, `plot`, `output`
(checked output paths), `run_folder` (what a training folder holds, and its rules),
`recipes` (the hyperparameter table), `engine` (what each training engine provides: its
checkpoint and trainer), `training` (stable-baselines3: environments, checkpoints,
sessions) and `ray_training`, `ray_algorithm`, `ray_files` (RLlib on Ray).
"""

from composer.cli.main import main

__all__ = ["main"]
