"""A user's own task module, registered with `composer --import tests.cli.own_tasks`: a task
and the recipe `composer train Swing` trains it with."""

from composer import registration
from composer.cli.recipes import Recipe, register
from tests.composer.scenes import SwingTask

registration.register(
    "Swing", "tests.composer.scenes:SwingTask", "keep a pendulum near its lowest point",
    time_limit=1.0,
)  # fmt: skip
register(SwingTask, Recipe("ppo", 4_096, 2, (16, 16), 1e-3, 64, n_steps=32, n_epochs=2))
