"""The `composer` command-line tool: list, show, run, view, train and evaluate tasks.

    $ composer list                            # or: python -m composer list
    $ composer show Reach --out reach.png      # the scene, and a frame of it
    $ composer run Reach --video reach.mp4     # a random policy, recorded
    $ composer view AntRun                     # MuJoCo's interactive viewer
    $ composer train                           # Reach, about five minutes on a laptop CPU
    $ composer eval Reach runs/Reach-ppo

From Python: `composer.cli.main(['list'])` returns the exit status. `train` needs its
engine's extra: `[train]` for stable-baselines3 (the default), `[ray]` for `--engine ray`,
each with torch; `eval` (and `--policy PATH` of `run` and `view`) the extra of the engine
that wrote the policy; the rest need only the base install (`run --video` also needs
imageio).

How the package is built: its modules form layers, each importing only from its own layer
and the layers listed before it, at module level, inside a function, by name (the engine
registry, the command table) or for type checks alike, with no circle; an engine's modules
are imported only by their own engine and by the registry, and only they import an
engine's library (stable-baselines3, torch, Ray, TensorBoard). tests/cli/test_cli_architecture.py
checks this on the real source.

    foundation:  errors arguments output progress video plot recipes catalog rollout describe
    contract:    engines.base engines.untrusted
    engines:     engines.sb3.files engines.sb3.encoder engines.sb3.policy engines.sb3.training
                 engines.sb3
                 engines.ray.files engines.ray.policy engines.ray.algorithm
                 engines.ray.instance engines.ray.training engines.ray
    registry:    engines
    commands:    run_folder listing show run view train evaluate
    entry:       main

`recipes` holds the recipe type and registry (each task's recipes live with the task:
`tasks/recipes.py`), `catalog` the registered tasks, `rollout` episodes, `describe` results
in words, `output` checked output paths, `arguments` the parser's rules; `engines` is the
registry of training engines and `engines.base` their contract (`composer.cli.engines`),
`engines.untrusted` how their plain policy readers check a stranger's file;
`run_folder` keeps the rules of a training run's folder for every engine.
"""

from composer.cli.main import main

__all__ = ["main"]
