"""docs/suite.md's table of tasks is the registry's: every Control Suite id, its flattened
observation and action sizes, its episode length (or "no limit") and benchmark tag, and
nothing else. On a mismatch the message holds the table as it should read."""

from __future__ import annotations

import math
from pathlib import Path

from gymnasium.spaces import flatdim

from tasks import suite

DOC = Path(__file__).resolve().parents[2] / "docs" / "suite.md"
HEADER = "| id | obs | act | steps x seconds | benchmarking | description |"


def expected_table() -> list[str]:
    """The table's rows as the registry says they should read."""
    rows = [HEADER, "| --- | ---: | ---: | --- | --- | --- |"]
    for (domain, task), entry in suite.TASKS.items():
        env = suite.load(domain, task, environment_kwargs={"flat_observation": True})
        # lqr's episodes have no time limit: they end when the system comes to rest.
        limited = math.isfinite(entry.time_limit)
        steps = math.ceil(entry.time_limit / env.control_timestep - 1e-9) if limited else "no limit"
        mark = "yes" if "benchmarking" in entry.tags else ""
        rows.append(
            f"| `{entry.env_id}` | {flatdim(env.observation_space)} | "
            f"{flatdim(env.action_space)} | {steps} x {env.control_timestep:g} | {mark} | "
            f"{entry.description} |"
        )
        env.close()
    return rows


def test_the_table_of_tasks_is_the_registry_s():
    lines = DOC.read_text().splitlines()
    start = lines.index(HEADER)
    table = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        table.append(line)
    expected = expected_table()
    assert table == expected, "docs/suite.md's table should read:\n" + "\n".join(expected)
