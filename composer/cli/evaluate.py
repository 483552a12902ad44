"""`composer eval TASK PATH`: mean and spread of a trained policy's return, and its success.

    $ composer eval Reach runs/Reach-ppo --episodes 100
    Reach, policy runs/Reach-ppo: return 59.03 ± 8.92 over 100 episodes, success rate 0.98

Actions are deterministic; episode i starts from seed `--seed` + i. The default seed is that
of the evaluations `composer train` runs (`rollout.EVAL_SEED`), so with `--episodes` equal to
training's `--eval-episodes` (10 by default, as here) it repeats training's last evaluation
exactly, on any engine.
"""

from __future__ import annotations

import argparse

from composer.cli import catalog, describe, engines, rollout


def run(args: argparse.Namespace) -> int:
    """Evaluate the policy; returns the exit status."""
    info = args.info
    env = catalog.make(info)
    try:
        policy = rollout.model_policy(engines.load_policy(args.policy, env, args.trust_policy))
        episodes = rollout.run_episodes(env, policy, args.episodes, args.seed)
    finally:
        env.close()
    stats = rollout.summary(episodes)
    print(f"{info.name}, policy {args.policy}: {describe.summary(stats)}")
    return 0
