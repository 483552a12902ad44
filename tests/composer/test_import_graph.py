"""The import graph of `composer` and the layering of the packages, checked on their real
source (ast), so that neither drifts silently:

- no import circle between composer's modules, neither at module level nor through imports
  inside functions (a deferred import is for an optional dependency, and says so);
- dependencies point one way, `tasks -> entities, arenas -> composer -> mjcf` (DESIGN.md):
  a package imports only packages of the layers below it.

`composer.cli` is left out while it is restructured (its engine registry comes later).
An import of a package (`from composer import Task`) counts as an import of its
`__init__`; the implicit import of a module's parent packages does not count.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import REPO

LAYERS = [["mjcf"], ["composer"], ["entities", "arenas"], ["tasks"]]
LEFT_OUT = ("composer.cli",)


class _Import:
    """One import statement of a module: the modules it names, and where it stands."""

    def __init__(self, module: str, node: ast.Import | ast.ImportFrom, where: str, line: str):
        self.module = module
        self.node = node
        self.where = where  # 'top', 'function' or 'typing' (under `if TYPE_CHECKING:`)
        self.line = line

    def targets(self, modules: set[str], package: bool) -> list[str]:
        """The dotted names this statement imports, as the modules of `modules` they
        resolve to where they are among them (a name from a package: its __init__)."""
        node = self.node
        if isinstance(node, ast.Import):
            return [_resolve(alias.name, modules) for alias in node.names]
        base = node.module or ""
        if node.level:
            parts = self.module.split(".")
            parts = parts[: len(parts) - node.level + (1 if package else 0)]
            base = ".".join([*parts, base] if base else parts)
        found = []
        for alias in node.names:
            full = f"{base}.{alias.name}"
            found.append(full if full in modules else _resolve(base, modules))
        return found


def _resolve(name: str, modules: set[str]) -> str:
    """`name`, or the innermost module of `modules` containing it; else `name`."""
    probe = name
    while probe and probe not in modules:
        probe = probe.rpartition(".")[0]
    return probe or name


@functools.cache
def _sources(package: str) -> dict[str, Path]:
    """{dotted module name: its file} of a package, but what is left out."""
    found = {}
    for path in sorted((REPO / package).rglob("*.py")):
        parts = list(path.relative_to(REPO).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        name = ".".join(parts)
        if not name.startswith(LEFT_OUT):
            found[name] = path
    return found


def _imports(package: str) -> Iterator[tuple[_Import, bool]]:
    """Every import statement of the package's modules, with whether its module is a
    package (__init__)."""
    for module, path in _sources(package).items():
        text = path.read_text()
        tree = ast.parse(text, str(path))
        lines = text.splitlines()
        parents = {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
        for node in ast.walk(tree):
            if not isinstance(node, ast.Import | ast.ImportFrom):
                continue
            where, parent = "top", parents.get(node)
            while parent is not None:
                if isinstance(parent, ast.If) and "TYPE_CHECKING" in ast.unparse(parent.test):
                    where = "typing"
                elif isinstance(parent, ast.FunctionDef | ast.AsyncFunctionDef):
                    where = "function" if where == "top" else where
                parent = parents.get(parent)
            line = lines[node.lineno - 1]
            yield _Import(module, node, where, line), path.name == "__init__.py"


@functools.cache
def _graph(deferred: bool) -> dict[str, frozenset[str]]:
    """composer's module imports of each other at run time: those at module level, and
    with `deferred` those inside functions too."""
    modules = set(_sources("composer"))
    edges: dict[str, set[str]] = {module: set() for module in modules}
    kinds = ("top", "function") if deferred else ("top",)
    for statement, package in _imports("composer"):
        if statement.where in kinds:
            for target in statement.targets(modules, package):
                if target in modules and target != statement.module:
                    edges[statement.module].add(target)
    return {module: frozenset(targets) for module, targets in edges.items()}


def _circles(graph: dict[str, frozenset[str]]) -> list[list[str]]:
    """The import circles of `graph`: its strongly connected sets of two or more modules
    (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                members = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    members.append(member)
                    if member == node:
                        break
                if len(members) > 1:
                    circles.append(sorted(members))
    return circles


def test_no_import_circle_at_module_level():
    assert _circles(_graph(deferred=False)) == []


def test_no_import_circle_through_imports_inside_functions():
    assert _circles(_graph(deferred=True)) == []


def test_an_import_of_composer_inside_a_function_says_why():
    modules = set(_sources("composer"))
    unexplained = [
        f"{statement.module}:{statement.node.lineno}: {ast.unparse(statement.node)}"
        for statement, package in _imports("composer")
        if statement.where == "function"
        and any(target in modules for target in statement.targets(modules, package))
        and "#" not in statement.line
    ]
    assert unexplained == []


@pytest.mark.parametrize("package", [name for layer in LAYERS for name in layer])
def test_imports_go_down_the_layers(package):
    layer = {name: depth for depth, names in enumerate(LAYERS) for name in names}
    upward = []
    for statement, is_package in _imports(package):
        for target in statement.targets(set(_sources(package)), is_package):
            top = target.split(".")[0]
            if top in layer and top != package and layer[top] >= layer[package]:
                upward.append(f"{statement.module}:{statement.node.lineno}: imports {target}")
    assert upward == []


def test_the_check_sees_what_it_should():
    """The graph holds the imports it should, and a circle in it would be found."""
    graph = _graph(deferred=True)
    assert "composer.task" in graph["composer.environment"]
    assert "composer.observation.schedule" in graph["composer.vector.observations"]
    assert "composer.dm_env_specs" in graph["composer.task"]  # an import in a function
    assert "composer.dm_env_specs" not in _graph(deferred=False)["composer.task"]
    assert "composer.stepping" not in _graph(deferred=True)["composer.batch_of_one"]
    looped = {**graph, "composer.errors": graph["composer.errors"] | {"composer.task"}}
    assert ["composer.errors", "composer.task"] in [
        [m for m in circle if m in ("composer.errors", "composer.task")]
        for circle in _circles(looped)
    ]
    assert not any(name.startswith("composer.cli") for name in graph)
