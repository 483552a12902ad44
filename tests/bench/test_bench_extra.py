"""`pip install -e '.[bench]'` brings what the benchmarks' other sides import: gymnasium's
MuJoCo environments (`python -m bench vector --against gymnasium`) import packages that
gymnasium itself lists under its own [mujoco] extra (imageio failed with "No module named
'imageio'" when the extra did not ask for them)."""

from __future__ import annotations

import ast
import importlib.metadata
import sys
from pathlib import Path

import gymnasium
import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

from tests.conftest import REPO

tomllib = pytest.importorskip("tomllib", reason="reading pyproject.toml needs Python 3.11")


def installed_by(requirements: list[str]) -> set[str]:
    """The distributions `requirements` install, with every requirement of theirs (and of
    the extras they name) that is installed here; those not installed count themselves."""
    found: set[str] = set()
    pending = [Requirement(text) for text in requirements]
    seen: set[tuple[str, frozenset[str]]] = set()
    while pending:
        requirement = pending.pop()
        name = canonicalize_name(requirement.name)
        key = (name, frozenset(requirement.extras))
        if key in seen:
            continue
        seen.add(key)
        found.add(name)
        try:
            theirs = importlib.metadata.requires(requirement.name) or []
        except importlib.metadata.PackageNotFoundError:
            continue
        for text in theirs:
            needed = Requirement(text)
            extras = ["", *requirement.extras]
            if needed.marker is None or any(needed.marker.evaluate({"extra": e}) for e in extras):
                pending.append(needed)
    return found


def top_level_imports(path: Path) -> set[str]:
    """The top-level packages a module imports at module level."""
    names = set()
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Import):
            names.update(alias.name.partition(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            names.add(node.module.partition(".")[0])
    return names


def test_the_bench_extra_brings_what_gymnasium_s_mujoco_environments_import():
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    installed = installed_by([*project["dependencies"], *project["optional-dependencies"]["bench"]])
    distributions = importlib.metadata.packages_distributions()
    imported = set().union(
        *(
            top_level_imports(p)
            for p in (Path(gymnasium.__file__).parent / "envs" / "mujoco").glob("*.py")
        )
    )
    missing = {}
    for module in sorted(imported - set(sys.stdlib_module_names)):
        providers = {canonicalize_name(d) for d in distributions.get(module, [module])}
        if not providers & installed:
            missing[module] = sorted(providers)
    assert "imageio" in imported and missing == {}
