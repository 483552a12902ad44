"""The Python in the README and docs/*.md runs as copied: every ```python block, in a fresh
Python from the clone's root (as a reader pastes it after `pip install -e '.[train]'`),
and every `gym.make(...)` written inline. A block that continues the one before it says so
in the text, and runs after it here (CONTINUES); a block that cannot run on this machine is
skipped with its reason, in SKIPPED. A `gym.make` line must never be skipped."""

from __future__ import annotations

import dataclasses
import re
import subprocess
import sys

import pytest

from tests.cli.helpers import environment
from tests.conftest import REPO

DOCS = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
_FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
# Inline code that calls gym.make: `gym.make("tasks:composer/Reach-v0")`.
_INLINE = re.compile(r"`([^`\n]*\bgym\.make\([^`\n]*)`")


@dataclasses.dataclass(frozen=True)
class Block:
    """A ```python block: its file, line and code; its key is the file and first line."""

    path: str
    line: int
    code: str

    @property
    def key(self) -> tuple[str, str]:
        return self.path, self.code.strip().splitlines()[0]


def python_blocks() -> list[Block]:
    """Every ```python block of DOCS, in order."""
    found = []
    for path in DOCS:
        text = path.read_text()
        for match in _FENCE.finditer(text):
            if match.group(1) == "python":
                line = text.count("\n", 0, match.start()) + 1
                found.append(Block(str(path.relative_to(REPO)), line, match.group(2)))
    return found


# Blocks that cannot run here, by file and first line: why, and where the same is tested.
SKIPPED = {
    ("README.md", "from entities import robots"): (
        "needs a MuJoCo Menagerie clone ($MENAGERIE_ROOT, ~/mujoco_menagerie) and the reader's "
        "my_arm.xml; tests/entities/test_robots.py runs each call on a folder laid out as "
        "Menagerie's"
    ),
    ("docs/ray.md", "import composer.rllib"): (
        "builds 8 env runners of 32 AntRun environments, which waits for a Ray cluster of 8 "
        "CPUs; tests/composer/test_rllib.py builds such configs on the session's cluster"
    ),
    ("docs/dm_control_composer.md", "# from dm_control import composer, mjcf"): (
        "MyDmControlTask stands for the reader's own dm_control task; dm_control's own tasks "
        "run so in tests/composer/test_dm_control_suite.py"
    ),
}
# Blocks that continue an earlier one of their file, by their first line: a line of the
# earlier block, and the code that runs them after it (the block itself, or a method of the
# class the earlier block defines, used).
CONTINUES = {
    (
        "README.md",
        "def get_reward_batch(self, physics):  # instead of get_reward: n rewards, shape (n,)",
    ): (
        "class Swing(composer.Task):",
        "class BatchedSwing(Swing):\n{block}\n\n"
        "env = composer.Environment(BatchedSwing(), time_limit=5.0)\n"
        "env.reset(seed=0)\n"
        "assert env.step(env.action_space.sample())[1] <= 0\n",
    ),
    ("README.md", '(capsule,) = upper.get_children("geom")  # the arm of the ten lines above'): (
        'arm = mjcf.RootElement(model="arm")',
        "{block}",
    ),
}


def earlier_block(block: Block, blocks: list[Block]) -> Block:
    """The block `block` continues (CONTINUES): the one of its file holding the line named."""
    line = CONTINUES[block.key][0]
    (earlier,) = (b for b in blocks if b.path == block.path and line in b.code.splitlines())
    return earlier


def program(block: Block, blocks: list[Block]) -> str:
    """The code that runs `block` as the reader would: alone, or after the block it continues."""
    if block.key not in CONTINUES:
        return block.code
    template = CONTINUES[block.key][1]
    return earlier_block(block, blocks).code + "\n" + template.format(block=block.code)


def run_python(code: str) -> subprocess.CompletedProcess[str]:
    """`code` in a fresh Python from the clone's root, headless."""
    return subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, env=environment(), capture_output=True,
        text=True, timeout=300,
    )  # fmt: skip


BLOCKS = python_blocks()


@pytest.mark.parametrize("block", BLOCKS, ids=[f"{b.path}:{b.line}" for b in BLOCKS])
def test_python_blocks_run_as_copied(block):
    if block.key in SKIPPED:
        assert "gym.make" not in block.code, "a gym.make line must run"
        pytest.skip(SKIPPED[block.key])
    result = run_python(program(block, BLOCKS))
    assert result.returncode == 0, f"{block.path}:{block.line}\n{result.stderr}"


def test_the_lists_of_special_blocks_name_blocks_that_exist():
    keys = {block.key for block in BLOCKS}
    assert set(SKIPPED) <= keys and set(CONTINUES) <= keys
    for block in BLOCKS:
        if block.key in CONTINUES:
            assert earlier_block(block, BLOCKS).line < block.line


def test_inline_gym_make_calls_run_as_copied():
    """Each complete call written inline (placeholders such as `id, ...` or an id the reader
    registers, 'composer/Swing-v0', and what a Shimmy user wrote before moving, left out) runs
    after `import gymnasium as gym` alone."""
    calls = {}
    for path in DOCS:
        for match in _INLINE.finditer(path.read_text()):
            call = match.group(1)
            if "..." in call or "(id," in call or "Swing-v0" in call or "shimmy" in call:
                continue
            calls[call] = path.relative_to(REPO)
    assert calls  # the README names some
    code = "import gymnasium as gym\n" + "".join(f"{call}.close()\n" for call in calls)
    result = run_python(code)
    assert result.returncode == 0, f"{sorted(calls.items())}\n{result.stderr}"
