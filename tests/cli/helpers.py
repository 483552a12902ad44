"""Run the `composer` command line in a subprocess, as a user would."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
# How `composer train` ends its refusal of a finished run, with either engine.
FINISHED_CHOICES = (
    "--resume continues it (to a larger --timesteps), --fresh replaces it, --out DIR trains "
    "elsewhere"
)


def environment(**extra: str) -> dict[str, str]:
    """The subprocess environment: this checkout first on the path, headless rendering."""
    path = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    return {**os.environ, "PYTHONPATH": path, "MUJOCO_GL": "egl", **extra}


def composer(
    *args: str, cwd: Path, env: dict[str, str] | None = None, timeout: float = 300
) -> subprocess.CompletedProcess[str]:
    """`python -m composer ARGS` in `cwd`; its exit status and output. The timeout only
    catches a command that never ends: a 5 s `composer eval` took over 120 s once, on a
    machine whose other processes left the suite a small share of its 2 cores."""
    return subprocess.run(
        [sys.executable, "-m", "composer", *args], cwd=cwd, env=env or environment(),
        capture_output=True, text=True, timeout=timeout, check=False,
    )  # fmt: skip


# The optional libraries a command may import: what `composer_without` reports.
LIBRARIES = ("stable_baselines3", "torch", "ray")


def blocker(blocked: tuple[str, ...]) -> str:
    """Python code that makes the packages `blocked` (and their submodules) impossible to
    import, as if they were not installed: a finder first on sys.meta_path."""
    return (
        "import sys\n"
        "class _NotInstalled:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        f"        if name.partition('.')[0] in {blocked!r}:\n"
        "            raise ModuleNotFoundError(f'No module named {name!r}', name=name)\n"
        "sys.meta_path.insert(0, _NotInstalled())\n"
    )


def composer_without(
    blocked: tuple[str, ...],
    *args: str,
    cwd: Path,
    env: dict[str, str] | None = None,
    timeout: float = 120,
) -> subprocess.CompletedProcess[str]:
    """The command line with the packages `blocked` uninstallable (as if not installed); its
    last line of output then lists the LIBRARIES that were imported anyway."""
    code = blocker(blocked) + (
        "from composer.cli import main\n"
        f"status = main({list(args)!r})\n"
        "print('imported:', sorted({m.split('.')[0] for m in sys.modules\n"
        f"      if sys.modules[m] is not None and m.split('.')[0] in {LIBRARIES!r}}}))\n"
        "sys.exit(status)\n"
    )
    return subprocess.run(
        [sys.executable, "-c", code], cwd=cwd, env=env or environment(),
        capture_output=True, text=True, timeout=timeout, check=False,
    )  # fmt: skip


def assert_one_line_error(result: subprocess.CompletedProcess[str], *fragments: str) -> str:
    """Exit status 2, one line on stderr holding every fragment, no traceback."""
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    return lines[0]
