"""docs/render_tasks.py: rendering the pictures again leaves the committed ones as they
are unless the scene changed, so a run does not dirty the repository with pixel noise."""

from __future__ import annotations

import shutil
import subprocess
import sys

from tests.cli.helpers import REPO, environment

IMAGES = REPO / "docs" / "images"


def render_tasks(*names: str, out) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(REPO / "docs" / "render_tasks.py"), *names, "--out", str(out)],
        env=environment(), capture_output=True, text=True, timeout=300, check=True,
    )  # fmt: skip


def test_pictures_are_rewritten_only_when_the_scene_looks_different(tmp_path):
    for name in ("Reach", "CartpoleSwingup"):
        shutil.copy(IMAGES / f"{name}.png", tmp_path / f"{name}.png")
    # Reach's picture replaced by another task's: that one must be rewritten.
    shutil.copy(IMAGES / "WalkerRun.png", tmp_path / "Reach.png")
    result = render_tasks("Reach", "CartpoleSwingup", out=tmp_path)
    assert "| `composer/Reach-v0` | 10 | 2 |" in result.stdout
    assert (tmp_path / "CartpoleSwingup.png").read_bytes() == (
        IMAGES / "CartpoleSwingup.png"
    ).read_bytes()
    rewritten = (tmp_path / "Reach.png").read_bytes()
    assert rewritten != (IMAGES / "WalkerRun.png").read_bytes()
    # The committed Reach picture is what a fresh render looks like: kept as it is.
    shutil.copy(IMAGES / "Reach.png", tmp_path / "Reach.png")
    render_tasks("Reach", out=tmp_path)
    assert (tmp_path / "Reach.png").read_bytes() == (IMAGES / "Reach.png").read_bytes()
