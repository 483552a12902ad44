"""One control step of a VectorEnvironment's environments, in `composer.stepping`'s order
and by its rules: the actions, the methods and hooks before the physics steps, MuJoCo's batch
stepping them with the observables sampled when due, the methods and hooks after, divergence,
the outcome (rewards, terminations, info, discounts), and an `action_repeat` step's further
control steps. `VectorEnvironment` inherits this (`ControlStep`); not used alone.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from mujoco import batch as mujoco_batch

from composer import hooks, stepping
from composer.batch import timer
from composer.batch.vector import VectorPhysics
from composer.vector import info_layout
from composer.vector.materialize import STALE, Materialize
from composer.vector.observations import BatchObservations


class ControlStep(Materialize):
    """The control steps of `VectorEnvironment` (its `step` runs `_step_envs`, then
    `_repeat`); a base of it, which sets these attributes (`__init__`), not used alone."""

    num_envs: int
    _every: np.ndarray  # every environment's id, read-only: "all of them" by identity
    _actions: stepping.ActionRule
    _methods: stepping.TaskStep
    _hooks: list[hooks.Hooks]
    _applies_each: bool
    _finishes_each: bool
    _substeps_hooked: bool
    _outcome_each: bool
    _observations: BatchObservations
    _substeps: int
    _action_repeat: int
    _step_limit: float
    _steps: np.ndarray
    _lag: int
    _most: int
    _invalid_counts: np.ndarray
    _constants: dict[tuple[Any, type], np.ndarray]

    def _step_counts(self) -> np.ndarray:
        """Control steps since each environment's reset, (num_envs,) int64, up to date."""
        if self._lag:
            self._steps += self._lag
            self._lag = 0
        return self._steps

    def _repeat(
        self,
        ids: np.ndarray,
        actions: np.ndarray,
        rewards: np.ndarray,
        terminated: np.ndarray,
        truncated: np.ndarray,
        info: dict[str, Any],
    ) -> dict[str, Any]:
        """The control steps after the first of an `action_repeat` step, for environments
        `ids` whose episodes go on, as each one's Environment runs them: rewards summed,
        discounts multiplied, each environment's info that of its last control step."""
        n = self.num_envs
        discounts = np.ones(n)
        _multiply_discounts(discounts, info, ids)
        for _ in range(1, self._action_repeat):
            going = ids[~(terminated[ids] | truncated[ids])]
            if not going.size:
                break
            more_rewards = np.zeros(n)
            more: dict[str, Any] = {}
            self._step_envs(going, actions[going], more_rewards, terminated, truncated, more)
            rewards[going] += more_rewards[going]
            _multiply_discounts(discounts, more, going)
            info_layout.replace_rows(info, more, going)
        if "discount" in info:
            has = info["_discount"]
            info["discount"][has] = discounts[has]
        return info

    def _step_envs(
        self,
        ids: np.ndarray,
        actions: np.ndarray,
        rewards: np.ndarray,
        terminated: np.ndarray,
        truncated: np.ndarray,
        info: dict[str, Any],
    ) -> bool:
        """One control step of environments `ids` (`self._every`: all) with their rows of
        `actions`; fills their rows of the results. Returns whether an episode may have
        ended (False: every row of `terminated` and `truncated` is False)."""
        actions = self._actions.clipped(actions, ids)
        every = ids is self._every
        physics = self._simulations.physics(None if every else ids)
        self._before_step(physics, ids, actions)
        phases, first = self._phases(ids)
        failures, last_due = self._advance(ids, actions, phases, first)
        self._after_step(physics, ids)
        if last_due:
            self._observations.sample(ids, phases, self._substeps, first)
        if every:
            self._lag += 1
            self._most += 1
        else:
            counts = self._step_counts()
            counts[ids] += 1
            self._most = int(counts.max())
        if self._observations.counts_steps:
            steps = self._step_counts()
            self._observations.finish(ids, (steps if every else steps[ids]) * self._substeps)
        errors_found = self._invalid(ids, failures)
        for i, message in errors_found.items():
            entries = stepping.diverged(message, stacklevel=3, environment=i)
            info_layout.add(info, entries, i, self.num_envs)
            truncated[i] = True
        ok = ids
        if errors_found:
            ok = ids[~np.isin(ids, list(errors_found))]
            physics = self._simulations.physics(ok)
        ending = bool(errors_found)
        if ok.size:
            ending |= self._outcome(physics, rewards, terminated, info)
            if self._most >= self._step_limit:  # some episode is at its step limit
                steps = self._step_counts()
                if ok is self._every:
                    np.greater_equal(steps, self._step_limit, out=truncated)
                else:
                    truncated[ok] = steps[ok] >= self._step_limit
                ending = True
        return ending

    def _before_step(self, physics: VectorPhysics, ids: np.ndarray, actions: np.ndarray) -> None:
        methods = self._methods
        if methods.apply(physics, actions):
            self._wrote(ids)
        if self._applies_each:
            for k, i in enumerate(ids):
                env, own = self._envs[i], self._materialize(i)
                methods.apply_each(env.task, self._hooks[i], own, actions[k], env.random_state)
                self._save(i)

    def _phases(self, ids: np.ndarray) -> tuple[int | np.ndarray, int | np.ndarray]:
        """The phases of the observation schedule of environments `ids` in this control
        step (one for all, or one each), and the physics steps each ran before it (0 when
        the schedule does not count them: `BatchObservations.counts_steps`)."""
        observations = self._observations
        if not observations.counts_steps:
            return 0, 0
        steps = self._step_counts()
        if ids is not self._every:
            steps = steps[ids]
        period = observations.period
        return (steps % period if period > 1 else 0), steps * self._substeps

    def _advance(
        self,
        ids: np.ndarray,
        actions: np.ndarray,
        phases: int | np.ndarray,
        first: int | np.ndarray,
    ) -> tuple[dict[int, str], bool]:
        """Run the control step's physics steps, sampling observables when due but after
        the last step (environments `ids` in schedule `phases`, after physics steps
        `first`). Returns the MuJoCo error message of each simulation that raised one, and
        whether observables are due after the last step."""
        failures: dict[int, str] = {}
        sample = self._observations.sample
        around = None
        if self._substeps_hooked:

            def around(before: bool) -> None:
                self._substep_hooks(ids, actions, before)

        return failures, stepping.physics_steps(
            self._substeps,
            self._observations.offsets(phases),
            lambda nstep: self._run(ids, nstep, failures),
            lambda offset: sample(ids, phases, offset, first),
            around,
        )

    def _substep_hooks(self, ids: np.ndarray, actions: np.ndarray, before: bool) -> None:
        for k, i in enumerate(ids):
            env = self._envs[i]
            physics = self._materialize(i)
            stepping.substep_hooks(self._hooks[i], physics, actions[k], env.random_state, before)
            self._save(i)

    def _run(self, ids: np.ndarray, nstep: int, failures: dict[int, str]) -> None:
        """Step simulations `ids` (but those that failed) by nstep physics steps."""
        if failures:
            ids = ids[~np.isin(ids, list(failures))]
        every = len(ids) == self.num_envs
        simulations = self._simulations
        consistent = self._envs[0].physics.legacy_step
        # The stages of the new state only once something reads them: before, the fields
        # are recomputed if read (a first read of a derived field, in this control step).
        computed = simulations.step_stage(consistent)
        try:
            timer.untimed(self._batch.step, None if every else ids, nstep, computed)
        except mujoco_batch.SimulationError as e:
            for i in e.ids:
                failures[int(i)] = f"MuJoCo raised: {self._batch.error(int(i))}"
        if every:
            if self._any_synced:  # else every environment's is STALE already
                self._held[:] = STALE
                self._any_synced = False
            simulations.stepped(None, consistent, computed)
        else:
            self._held[ids] = STALE
            simulations.stepped(ids, consistent, computed)

    def _after_step(self, physics: VectorPhysics, ids: np.ndarray) -> None:
        methods = self._methods
        if methods.finish(physics):
            self._wrote(ids)
        if self._finishes_each:
            for i in ids:
                env, own = self._envs[i], self._materialize(i)
                methods.finish_each(env.task, self._hooks[i], own, env.random_state)
                self._save(i)

    def _invalid(self, ids: np.ndarray, failures: dict[int, str]) -> dict[int, str]:
        """{environment: message} of the stepped environments whose state is invalid."""
        found = dict(failures)
        if not np.count_nonzero(self._invalid_counts):
            return found  # no warning of an invalid state anywhere
        counts = self._invalid_counts[ids]
        for i in ids[counts.any(axis=1)]:
            if int(i) not in found:
                message = stepping.invalid_state(self._materialize(i))
                if message is not None:
                    found[int(i)] = message
        return found

    def _outcome(
        self,
        physics: VectorPhysics,
        rewards: np.ndarray,
        terminated: np.ndarray,
        info: dict[str, Any],
    ) -> bool:
        """Reward, termination, info entries and discount of the environments of
        `physics`; whether an episode may have terminated (False: none did)."""
        methods, n = self._methods, self.num_envs
        ids = physics._every
        every = slice(None) if physics.num_envs == n else ids
        rows = methods.outcome(physics)
        if rows.rewards is not None:
            rewards[every] = rows.rewards
        ending = rows.terminations is not None and rows.terminations is not False
        if ending:
            terminated[every] = rows.terminations
        for key, values in rows.info.items():
            info_layout.put(info, key, ids, values, n)
        if rows.discounts is not None:
            discounts = rows.discounts
            if type(every) is slice and not isinstance(discounts, np.ndarray):
                info["discount"] = self._constant_rows(discounts, np.float64)  # Task's default
                info["_discount"] = self._constant_rows(True, bool)
            else:
                info_layout.put(info, "discount", ids, np.broadcast_to(discounts, len(ids)), n)
        if self._outcome_each:
            ending = True
            for i in ids:
                task, own = self._envs[i].task, self._materialize(i)
                reward, ended, entries = methods.outcome_each(task, own)
                if reward is not None:
                    rewards[i] = reward
                if ended is not None:
                    terminated[i] = ended
                info_layout.add(info, entries, i, n)
        return ending

    def _constant_rows(self, value: Any, dtype: type) -> np.ndarray:
        """A new (num_envs,) array of `value`: a copy of one made once (a copy costs less
        than filling one)."""
        key = (value, dtype)
        rows = self._constants.get(key)
        if rows is None:
            rows = self._constants[key] = np.full(self.num_envs, value, dtype=dtype)
        return rows.copy()


def _multiply_discounts(discounts: np.ndarray, info: dict[str, Any], ids: np.ndarray) -> None:
    """discounts[ids] *= the step's discount of each of `ids` (0 where it has none: a
    diverged step, as a single Environment counts it)."""
    if "discount" in info:
        discounts[ids] *= np.where(info["_discount"][ids], info["discount"][ids], 0.0)
    else:
        discounts[ids] = 0.0
