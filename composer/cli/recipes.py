"""Training recipes: the default algorithm and hyperparameters of each task, in one table.

    recipe = recipes.for_task('Reach')                # the task's default algorithm
    recipe = recipes.for_task('Reach', algo='ppo')    # that algorithm's row, or its generic one
    recipe = recipe.replace(timesteps=2048, n_envs=2) # command-line overrides
    recipe.algo_kwargs()                              # keywords for PPO(...) / SAC(...)

A task without a row trains with the generic recipe of the algorithm. `VEC` picks how the
K environments run: 'dummy' steps them in this process (fastest for cheap tasks: no
inter-process traffic), 'subproc' gives each its own process (for costly physics),
'batched' steps them all on MuJoCo's thread pool (`composer.vector` through `composer.sb3`;
it pays off when the task declares batched rewards and observations: without them Reach
ran at 4,000 steps/s batched against 5,700 in-process with 8 environments on 2 cores).
"""

from __future__ import annotations

import dataclasses
from typing import Any

ALGORITHMS = ("ppo", "sac")
# The fields only one algorithm reads.
_ONLY = {
    "ppo": ("n_steps", "n_epochs", "ent_coef"),
    "sac": ("buffer_size", "learning_starts", "train_freq", "gradient_steps"),
}
VEC = ("dummy", "subproc", "batched")
DEFAULT_TASK = "Reach"


@dataclasses.dataclass(frozen=True)
class Recipe:
    """How to train: algorithm, budget, parallel environments and hyperparameters."""

    algo: str
    timesteps: int
    n_envs: int
    net: tuple[int, ...]
    learning_rate: float
    batch_size: int
    gamma: float = 0.99
    vec: str = "dummy"
    # Observations and rewards scaled by running statistics (VecNormalize); the observation
    # statistics are saved inside the policy .zip, so `run` and `eval` apply them too.
    normalize: bool = False
    # PPO: steps per environment per update, epochs over them, entropy bonus.
    n_steps: int = 256
    n_epochs: int = 10
    ent_coef: float = 0.0
    # SAC: replay size, random steps first, environment steps and gradient steps per update.
    buffer_size: int = 300_000
    learning_starts: int = 5_000
    train_freq: int = 1
    gradient_steps: int = 1

    def replace(self, **changes: Any) -> Recipe:
        """A copy with `changes` (None values are ignored)."""
        return dataclasses.replace(self, **{k: v for k, v in changes.items() if v is not None})

    def algo_kwargs(self) -> dict[str, Any]:
        """The keyword arguments of the stable-baselines3 algorithm's constructor."""
        common = {
            "learning_rate": self.learning_rate,
            "batch_size": self.batch_size,
            "gamma": self.gamma,
            "policy_kwargs": {"net_arch": list(self.net)},
        }
        if self.algo == "ppo":
            return {**common, "n_steps": self.n_steps, "n_epochs": self.n_epochs,
                    "ent_coef": self.ent_coef}  # fmt: skip
        return {
            **common,
            "buffer_size": self.buffer_size,
            "learning_starts": self.learning_starts,
            "train_freq": self.train_freq,
            "gradient_steps": self.gradient_steps,
        }

    def table(self) -> dict[str, Any]:
        """The fields this recipe's algorithm uses, for printing and for metrics.json."""
        others = {f for algo, fields in _ONLY.items() if algo != self.algo for f in fields}
        return {k: v for k, v in dataclasses.asdict(self).items() if k not in others}

    @classmethod
    def from_table(cls, table: dict[str, Any]) -> Recipe:
        """The recipe whose `table()` (read back from JSON) is `table`."""
        return cls(**{**table, "net": tuple(table["net"])})


GENERIC = {
    "ppo": Recipe("ppo", 1_000_000, 8, (64, 64), 3e-4, 256, normalize=True),
    "sac": Recipe("sac", 100_000, 1, (256, 256), 3e-4, 256),
}

# One row per (task, algorithm), measured on a 2-core CPU; a task's first row is its default.
# fmt: off
RECIPES: dict[tuple[str, str], Recipe] = {
    # (task, algo):             Recipe(algo, timesteps, n_envs, net, learning_rate, batch_size, ...)
    ("Reach", "ppo"):           Recipe("ppo", 800_000, 16, (64, 64), 3e-4, 256, gamma=0.95,
                                       normalize=True, n_steps=128, vec="batched"),
    ("CartpoleSwingup", "ppo"): Recipe("ppo", 300_000, 16, (64, 64), 3e-4, 256,
                                       normalize=True, vec="batched"),
    ("AntRun", "ppo"):          Recipe("ppo", 2_000_000, 16, (64, 64), 3e-4, 256,
                                       normalize=True, vec="batched"),
    ("WalkerRun", "ppo"):       Recipe("ppo", 2_000_000, 16, (64, 64), 3e-4, 256,
                                       normalize=True, vec="batched"),
    ("ArmPushBox", "ppo"):      Recipe("ppo", 1_200_000, 16, (128, 128), 3e-4, 256,
                                       gamma=0.98, normalize=True, n_steps=128, vec="batched"),
}
# fmt: on


def default_algo(task: str) -> str:
    """The algorithm of `task`'s first row, PPO for a task without one."""
    return next((algo for name, algo in RECIPES if name == task), "ppo")


def for_task(task: str, algo: str | None = None) -> Recipe:
    """The recipe for `task` with `algo` (default: the task's default algorithm)."""
    algo = algo or default_algo(task)
    return RECIPES.get((task, algo), GENERIC[algo])
