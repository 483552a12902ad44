"""Every module of the packages opens with a short map of itself: what it is for, an example
where it has a public use, its promises, in at most ten lines (issue 40). Longer rules live
with the class or function they govern, figures in docs/performance_profile.md."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PACKAGES = ("mjcf", "composer", "entities", "arenas", "tasks")
LONGEST = 10


def docstring_lines(path: Path) -> int:
    """The module docstring's line count (0: none)."""
    docstring = ast.get_docstring(ast.parse(path.read_text()), clean=False)
    return len(docstring.strip().splitlines()) if docstring else 0


@pytest.mark.parametrize("package", PACKAGES)
def test_every_module_has_a_docstring_of_at_most_ten_lines(package: str) -> None:
    modules = sorted((REPO / package).rglob("*.py"))
    assert modules
    lengths = {str(p.relative_to(REPO)): docstring_lines(p) for p in modules}
    assert [m for m, n in lengths.items() if not 1 <= n <= LONGEST] == []
