"""composer.vector: many environments of one task, stepped by MuJoCo's native batch.

    from composer.vector import VectorEnvironment
    venv = VectorEnvironment(Swing, num_envs=64, time_limit=10.0)   # Swing: a Task class
    obs, info = venv.reset(seed=0)                   # same as 64 Environments, seeds 0..63
    for _ in range(1000):
        obs, reward, terminated, truncated, info = venv.step(policy(obs))   # (64, ...) each
    venv.per_environment            # what runs per environment each step ([]: all batched)

    class Swing(composer.Task):                      # per-step methods in batched form
        def get_reward_batch(self, physics):         # physics: a BatchPhysics, n rows
            return -np.abs(physics.bind(self.hinge).qpos[:, 0])

Physics steps run on MuJoCo's thread pool (`mujoco.batch.Batch`); what the task computes
per step runs over all environments at once where it is written in batched form
(`composer.batch`, which a single `composer.Environment` runs too, with a batch of one)
and its observables are batchable (`MJCFFeature`s are; `BatchGeneric` for functions;
`composer.vector.observations`). Anything else runs per environment, correctly, on a
materialized MjData. The trajectories equal those of single `composer.Environment`s with
the same seeds (`composer.vector.environment` says exactly what is promised).
`gym.make_vec(id, num_envs, vectorization_mode='vector_entry_point')` builds one through
`make_vector_environment`; `composer.sb3.VecEnvAdapter` serves one to stable-baselines3.
Camera observables are drawn for every environment at once on render threads
(`composer.vector.rendering`); `PixelVectorEnvironment` observes every environment through
a camera, as `composer.PixelEnvironment` one (`make_vec(..., pixels=True)`).
`BatchPhysics`, `BatchedTask`, `BatchGeneric` and `BatchError` are composer's, exported
here too.
"""

from composer.batch.protocol import BatchedTask, BatchPhysics
from composer.batch.vector import BatchBinding, VectorPhysics
from composer.errors import BatchError
from composer.observation import BatchGeneric
from composer.vector.environment import VectorEnvironment
from composer.vector.make import make_vector_environment
from composer.vector.pixels import PixelVectorEnvironment

__all__ = [
    "BatchBinding",
    "BatchError",
    "BatchGeneric",
    "BatchPhysics",
    "BatchedTask",
    "PixelVectorEnvironment",
    "VectorEnvironment",
    "VectorPhysics",
    "make_vector_environment",
]
