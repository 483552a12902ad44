"""A user's own task module, registered with `composer --import tests.cli.own_tasks`."""

from composer import registration

registration.register(
    "Swing", "tests.composer.scenes:SwingTask", "keep a pendulum near its lowest point",
    time_limit=1.0,
)  # fmt: skip
