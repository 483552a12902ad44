"""`composer list`: every registered task, its sizes and description."""

from __future__ import annotations

import re

import tasks
from composer import registration
from tests.cli.helpers import composer


def test_list_shows_every_registered_task_with_its_sizes(tmp_path):
    result = composer("list", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["task", "id", "obs", "act", "description"]
    rows = {line.split()[0]: line for line in lines[1:] if line}
    assert set(rows) == {info.name for info in registration.registered().values()
                         if info.env_id in (*tasks.IDS, *tasks.suite.IDS)}  # fmt: skip
    # composer's tasks, then the Control Suite's, a group per domain.
    ids = [line.split()[1] for line in lines[1:] if line]
    assert ids[: len(tasks.IDS)] == sorted(tasks.IDS)
    suite = [tasks.suite.find(domain, task).env_id for domain, task in tasks.suite.ALL_TASKS]
    assert ids[len(tasks.IDS) :] == suite  # by domain, each domain's tasks in its order
    two_poles = r"dm_control/cartpole-two_poles-v0\s+8\s+1\s+Swing"
    assert re.search(two_poles, rows["cartpole-two_poles"])
    assert re.search(
        r"^Reach\s+composer/Reach-v0\s+10\s+2\s+Move a planar 2-link arm", rows["Reach"]
    )
    assert re.search(r"composer/CartpoleSwingup-v0\s+5\s+1\s+Swing", rows["CartpoleSwingup"])
