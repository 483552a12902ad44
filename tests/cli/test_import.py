"""`composer --import MODULE`: a user's own tasks next to the shipped ones."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.cli.helpers import assert_one_line_error, composer, environment

MY_TASKS = """from composer import registration
registration.register("Swing", "tests.composer.scenes:SwingTask", "a pendulum", time_limit=1.0)
"""


def test_imported_tasks_are_listed_and_run(tmp_path):
    listed = composer("--import", "tests.cli.own_tasks", "list", cwd=tmp_path)
    assert listed.returncode == 0, listed.stderr
    assert any(line.split()[:4] == ["Swing", "composer/Swing-v0", "3", "1"]
               for line in listed.stdout.splitlines())  # fmt: skip
    ran = composer("--import", "tests.cli.own_tasks", "run", "swing", cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr
    assert "return" in ran.stdout and "50 steps" in ran.stdout


def test_a_module_that_does_not_exist_is_one_line(tmp_path):
    result = composer("--import", "no_such_module", "list", cwd=tmp_path)
    assert_one_line_error(result, "cannot import 'no_such_module'")


@pytest.mark.skipif(sys.version_info < (3, 11), reason="python -P: from 3.11")
def test_the_composer_script_imports_a_module_from_the_current_folder(tmp_path):
    """As the installed `composer` script runs: the script's folder on sys.path, not the
    current one (python -P -c), and yet my_tasks.py in the current folder is found."""
    (tmp_path / "my_tasks.py").write_text(MY_TASKS)
    script = "import sys; from composer.cli import main; sys.exit(main())"
    result = subprocess.run(
        [sys.executable, "-P", "-c", script, "--import", "my_tasks", "run", "Swing"],
        cwd=tmp_path, env=environment(), capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "Swing, random policy: return" in result.stdout
