"""`composer eval TASK PATH`: mean and spread of a trained policy's return, and its success.

    $ composer eval Reach runs/Reach-ppo --episodes 100
    Reach, policy runs/Reach-ppo: return 59.03 ± 8.92 over 100 episodes, success rate 0.98

Actions are deterministic; episode i starts from seed `--seed` + i. The default seed is that
of the evaluations `composer train` runs (`rollout.EVAL_SEED`), so with `--episodes` equal to
training's `--eval-episodes` (10 by default, as here) it repeats training's last evaluation
exactly, on either engine.
"""

from __future__ import annotations

import argparse

from composer.cli import catalog, rollout, training


def run(args: argparse.Namespace) -> int:
    """Evaluate the policy; returns the exit status."""
    info = args.info
    env = catalog.make(info)
    try:
        model = training.load_policy(args.policy, env, args.trust_policy)
        episodes = rollout.run_episodes(env, rollout.model_policy(model), args.episodes, args.seed)
    finally:
        env.close()
    stats = rollout.summary(episodes)
    print(f"{info.name}, policy {args.policy}: {rollout.describe_summary(stats)}")
    return 0
