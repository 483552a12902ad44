"""composer.vector: many environments of one task, stepped by MuJoCo's native batch.

    venv = composer.vector.VectorEnvironment(Swing, num_envs=64, time_limit=10.0)
    obs, info = venv.reset(seed=0)                   # same as 64 Environments, seeds 0..63
    obs, reward, terminated, truncated, info = venv.step(policy(obs))   # (64, ...) each
    venv.per_environment            # what runs per environment each step ([]: all batched)

Promise: the same trajectories, bit for bit, as single `composer.Environment`s with the same
seeds (`VectorEnvironment` states each promise); what is not batched runs per environment.
`gym.make_vec(id, n, vectorization_mode='vector_entry_point')` makes one.
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
