"""`composer list`: every registered task with its observation and action sizes.

    $ composer list
    task             id                           obs  act  description
    CartpoleSwingup  composer/CartpoleSwingup-v0    5    1  Swing a hanging pole up and ...
    Reach            composer/Reach-v0             10    2  Move a planar 2-link arm's ...

composer's own tasks come first, then the Control Suite's (`dm_control/DOMAIN-TASK-v0`), a
group per domain; a task that cannot be built is listed with the reason instead of sizes.
"""

from __future__ import annotations

import argparse

from gymnasium.spaces import flatdim

import mjcf
from composer import errors, registration
from composer.cli import catalog


def run(args: argparse.Namespace) -> int:
    """Print the table of tasks; returns the exit status. Each task is built once to read
    its sizes; one that cannot be built (say, a robot whose model files are not installed)
    is listed with the reason instead of sizes."""
    rows: list[tuple[str, ...]] = []
    known = catalog.tasks()
    registered = {env_id: i for i, env_id in enumerate(registration.registered())}

    def place(item: tuple[str, registration.TaskInfo]) -> tuple[tuple[bool, str, str], int, str]:
        name, info = item
        group = _group(info)
        return (group, registered[info.env_id] if group[0] else 0, name)

    listed = sorted(known.items(), key=place)
    group = None
    for name, info in listed:
        if group is not None and _group(info) != group:
            rows.append(("",) * 5)  # a blank line between groups
        group = _group(info)
        description = info.description
        try:
            env = catalog.make(info)
        except (errors.Error, mjcf.Error, OSError) as e:
            obs = act = "-"
            description = f"{description} (unavailable: {' '.join(str(e).split())})"
        else:
            obs = str(flatdim(env.observation_space))
            act = str(flatdim(env.action_space))
            env.close()
        rows.append((name, info.env_id, obs, act, description))
    if not rows:
        print("no tasks are registered")
        return 0
    header = ("task", "id", "obs", "act", "description")
    widths = [max(len(row[i]) for row in [header, *rows]) for i in range(4)]
    for row in [header, *rows]:
        if not row[0]:
            print()
            continue
        print(
            f"{row[0]:<{widths[0]}}  {row[1]:<{widths[1]}}  "
            f"{row[2]:>{widths[2]}}  {row[3]:>{widths[3]}}  {row[4]}"
        )
    return 0


def _group(info: registration.TaskInfo) -> tuple[bool, str, str]:
    """Where a task is listed: composer's own first (by name), then each other namespace's
    (the Control Suite's `dm_control/DOMAIN-TASK`) a group per domain, its tasks in the
    order they were registered."""
    namespace, _, rest = info.env_id.partition("/")
    if namespace == registration.NAMESPACE:
        return (False, "", "")
    return (True, namespace, rest.partition("-")[0])
