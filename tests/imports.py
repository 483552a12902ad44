"""The import statements of the repository's packages, read from their source (ast): one
classifier for the architecture tests of mjcf (tests/mjcf/test_architecture.py) and of
the packages (tests/composer/test_import_graph.py).

    for statement in imports('mjcf'):
        statement.module, statement.where, statement.targets(modules('mjcf'))

An import of a package (`from composer import Task`) counts as an import of its
`__init__`; the implicit import of a module's parent packages does not count.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator
from pathlib import Path

from tests.conftest import REPO


class Import:
    """One import statement of a module: the modules it names, and where it stands."""

    def __init__(
        self, module: str, node: ast.Import | ast.ImportFrom, where: str, line: str, package: bool
    ) -> None:
        self.module = module
        self.node = node
        self.where = where  # 'top', 'function' or 'typing' (under `if TYPE_CHECKING:`)
        self.line = line
        self.package = package  # whether `module` is a package (its __init__)

    def targets(self, known: set[str] | dict[str, Path]) -> list[str]:
        """The dotted names this statement imports, as the modules of `known` they resolve
        to where they are among them (a name from a package: its __init__)."""
        node = self.node
        if isinstance(node, ast.Import):
            return [_resolve(alias.name, known) for alias in node.names]
        base = node.module or ""
        if node.level:
            parts = self.module.split(".")
            parts = parts[: len(parts) - node.level + (1 if self.package else 0)]
            base = ".".join([*parts, base] if base else parts)
        found = []
        for alias in node.names:
            full = f"{base}.{alias.name}"
            found.append(full if full in known else _resolve(base, known))
        return found

    def __str__(self) -> str:
        return f"{self.module}:{self.node.lineno}: {ast.unparse(self.node)}"


def _resolve(name: str, known: set[str] | dict[str, Path]) -> str:
    """`name`, or the innermost module of `known` containing it; else `name`."""
    probe = name
    while probe and probe not in known:
        probe = probe.rpartition(".")[0]
    return probe or name


@functools.cache
def modules(package: str, left_out: tuple[str, ...] = ()) -> dict[str, Path]:
    """{dotted module name: its file} of a package (a package's own name for its
    __init__), but the modules under `left_out`."""
    found = {}
    for path in sorted((REPO / package).rglob("*.py")):
        parts = list(path.relative_to(REPO).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        name = ".".join(parts)
        if not (left_out and name.startswith(left_out)):
            found[name] = path
    return found


@functools.cache
def syntax(path: Path) -> tuple[ast.Module, tuple[str, ...]]:
    """A file's syntax tree and its lines."""
    text = path.read_text()
    return ast.parse(text, str(path)), tuple(text.splitlines())


def imports(package: str, left_out: tuple[str, ...] = ()) -> Iterator[Import]:
    """Every import statement of the package's modules (but those under `left_out`)."""
    for module, path in modules(package, left_out).items():
        tree, lines = syntax(path)
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
            package_init = path.name == "__init__.py"
            yield Import(module, node, where, lines[node.lineno - 1], package_init)


def graph(
    package: str, deferred: bool, left_out: tuple[str, ...] = ()
) -> dict[str, frozenset[str]]:
    """The package's module imports of each other at run time: those at module level,
    and with `deferred` those inside functions too."""
    known = modules(package, left_out)
    edges: dict[str, set[str]] = {module: set() for module in known}
    kinds = ("top", "function") if deferred else ("top",)
    for statement in imports(package, left_out):
        if statement.where in kinds:
            for target in statement.targets(known):
                if target in known and target != statement.module:
                    edges[statement.module].add(target)
    return {module: frozenset(targets) for module, targets in edges.items()}


def circles(graph: dict[str, frozenset[str]]) -> list[list[str]]:
    """The import circles of `graph`: its strongly connected sets of two or more modules
    (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
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
                    found.append(sorted(members))
    return found
