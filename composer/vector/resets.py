"""Resetting a VectorEnvironment's environments: `reset()` (all, or those of a mask, with
seeds) and the resets of Gymnasium's autoreset modes after an episode ends (NEXT_STEP's at
the next step, SAME_STEP's at once, its final observations and info kept). Each environment
resets as its own `composer.Environment`. `VectorEnvironment` inherits this (`Resets`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import gymnasium
import numpy as np

from composer import errors, hooks
from composer.vector import info_layout
from composer.vector.materialize import SYNCED, Materialize
from composer.vector.observations import BatchObservations
from composer.vector.rendering import RenderThreads
from mjcf.sim import rendering


class Resets(Materialize, gymnasium.vector.VectorEnv):
    """The resets of `VectorEnvironment`, a base of it, which sets these attributes
    (`__init__`) and defines the methods named here; not used alone."""

    _render_threads: RenderThreads
    _hooks: list[hooks.Hooks]
    _observations: BatchObservations
    _over: np.ndarray  # whether each environment's episode ended
    _ended: bool  # whether some environment's episode ended (_over.any())
    _most: int
    _started: bool
    _step_counts: Callable[[], np.ndarray]
    _set_models: Callable[[np.ndarray], None]
    _resolve_hooks: Callable[[], None]

    def reset(
        self,
        *,
        seed: int | Sequence[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, dict[str, Any]]:
        """Reset every environment, or those of `options['reset_mask']` (a (num_envs,)
        bool array). `seed`: an int seeds environment i with seed + i, a list one seed
        each. Returns (observations, info). Raises EpisodeError for a bad mask or seeds."""
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        seeds = _seeds(seed, self.num_envs)
        if seed is not None and _is_seed(seed):
            super().reset(seed=seeds[0])
        if mask is None:
            ids = np.arange(self.num_envs)
        else:
            mask = np.asarray(mask)
            if mask.dtype != np.bool_ or mask.shape != (self.num_envs,) or not mask.any():
                raise errors.EpisodeError(
                    f"options['reset_mask'] must be a ({self.num_envs},) bool array with a "
                    f"True, got {mask!r}"
                )
            ids = np.flatnonzero(mask)
        self._reset_envs(ids, [seeds[i] for i in ids], options or None)
        self._started = True
        return self._observations.observation(), {}

    def _reset_envs(
        self, ids: np.ndarray, seeds: Sequence[int | None], options: dict[str, Any] | None
    ) -> None:
        for i, seed in zip(ids, seeds, strict=True):
            env = self._envs[i]
            model = env.physics.model
            with rendering.context_group(self._render_threads.group(i)):
                env.reset(seed=seed, options=options)
            if env.physics.model is not model:  # recompiled: its hooks may have changed
                self._hooks[i] = hooks.Hooks(env.task)
                if i == 0:
                    self._resolve_hooks()
            self._save(i)
            self._observations.load(i, env.updater)
            self._held[i] = SYNCED
        counts = self._step_counts()
        counts[ids] = 0
        self._most = int(counts.max())
        self._over[ids] = False
        self._ended = bool(self._over.any())
        self._any_synced = True
        self._set_models(ids)

    def _final(self, ended: np.ndarray, info: dict[str, Any]) -> dict[str, Any]:
        """SAME_STEP: move ended environments' observations and info to final_obs and
        final_info, then reset them."""
        mask = np.zeros(self.num_envs, dtype=bool)
        mask[ended] = True
        final_obs = np.full(self.num_envs, None, dtype=object)
        for i, row in zip(ended, self._final_observations(ended), strict=True):
            final_obs[i] = row
        kept, moved = info_layout.split(info, mask)
        self._reset_envs(ended, [None] * len(ended), None)
        return {**kept, "final_obs": final_obs, "_final_obs": mask, "final_info": moved,
                "_final_info": mask.copy()}  # fmt: skip

    def _final_observations(self, ended: np.ndarray) -> list[Any]:
        """The observations environments `ended` end their episodes with, before their
        reset, each as its own Environment returns it."""
        return [self._observations.row(i) for i in ended]


def _is_seed(seed: Any) -> bool:
    """Whether `seed` is one seed: an int (numpy's too) of at least 0, as Gymnasium takes."""
    return isinstance(seed, int | np.integer) and bool(seed >= 0)


def _seeds(seed: Any, n: int) -> list[int | None]:
    """The seed of each of `n` environments that `seed` gives (see `reset`); raises
    EpisodeError, before any environment is reset, for anything else."""
    if seed is None or _is_seed(seed):
        return [None if seed is None else int(seed) + i for i in range(n)]
    if (
        isinstance(seed, list | tuple | np.ndarray)
        and len(seed) == n
        and all(s is None or _is_seed(s) for s in seed)
    ):
        return [None if s is None else int(s) for s in seed]
    shown = repr(seed) if len(repr(seed)) <= 80 else repr(seed)[:77] + "..."
    raise errors.EpisodeError(
        f"seed must be None, an int of at least 0 (environment i gets seed + i) or {n} of "
        f"them (or None), got {shown}"
    )
