"""`composer --import MODULE`: a user's own tasks next to the shipped ones."""

from __future__ import annotations

from tests.cli.helpers import assert_one_line_error, composer


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
