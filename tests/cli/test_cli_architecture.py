"""The architecture of `composer.cli`, checked on its real source (ast) so that it cannot
drift silently (the package docstring describes it):

- every import between CLI modules goes down the layers the package docstring lists, or
  stays in its layer: at module level, inside a function, by name in a string (the engine
  registry, the command table) and for type checks alike; and none closes a circle;
- an engine's modules are imported only by that engine's modules and by the registry, and
  the engines' libraries (and composer's adapters to them) only by an engine's modules;
- no CLI module imports the shipped `tasks` (catalog finds them by name; their recipes
  register themselves).

An import of `a.b.c` is an edge to `a.b.c`, not to the packages it runs first; the package
`composer.cli` itself only imports `main`.
"""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Iterator
from pathlib import Path

import composer.cli

PACKAGE = Path(composer.cli.__file__).parent
PREFIX = "composer.cli."
# The libraries only an engine imports, and composer's adapters to them.
ENGINE_LIBRARIES = ("stable_baselines3", "torch", "ray", "tensorboard", "composer.sb3",
                    "composer.rllib")  # fmt: skip


@functools.cache
def cli_modules() -> dict[str, ast.Module]:
    """{module name relative to composer.cli ('engines.sb3.files'): its syntax tree}."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        found[name] = ast.parse(path.read_text(), str(path))
    del found[""]  # composer.cli itself: `from composer.cli.main import main`
    return found


def _layer_list() -> list[list[str]]:
    """The modules of each layer, as the package docstring lists them."""
    layers: list[list[str]] = []
    for line in (composer.cli.__doc__ or "").splitlines():
        match = re.fullmatch(r" {4}(\w+):\s+([\w. ]+)", line)
        if match:
            layers.append(match.group(2).split())
        elif layers and re.fullmatch(r" {6,}[\w. ]+", line):
            layers[-1].extend(line.split())
    return layers


def _layers() -> dict[str, int]:
    return {module: index for index, modules in enumerate(_layer_list()) for module in modules}


def _resolve(name: str) -> str | None:
    """The CLI module `name` ('composer.cli.engines.ray.files.NAME') is or is in."""
    if not name.startswith(PREFIX):
        return None
    name = name.removeprefix(PREFIX)
    while name and name not in cli_modules():
        name = name.rpartition(".")[0]
    return name or None


def _imports() -> Iterator[tuple[str, str, str, int]]:
    """(module, imported name, 'top' | 'function' | 'typing' | 'string', line) for every
    import statement (`from a import b`: 'a.b') and every string naming a CLI module."""
    for module, tree in cli_modules().items():
        parents = {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [f"{node.module}.{alias.name}" for alias in node.names]
            elif isinstance(node, ast.Constant) and isinstance(node.value, str):
                if not node.value.startswith(PREFIX):
                    continue
                yield module, node.value, "string", node.lineno
                continue
            else:
                continue
            where, parent = "top", parents.get(node)
            while parent is not None:
                if isinstance(parent, ast.If) and "TYPE_CHECKING" in ast.unparse(parent.test):
                    where = "typing"
                elif isinstance(parent, ast.FunctionDef | ast.AsyncFunctionDef) and where == "top":
                    where = "function"
                parent = parents.get(parent)
            for name in names:
                yield module, name, where, node.lineno


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Every import between CLI modules, of any kind."""
    graph: dict[str, set[str]] = {module: set() for module in cli_modules()}
    for module, name, _, _ in _imports():
        target = _resolve(name)
        if target is not None and target != module:
            graph[module].add(target)
    return graph


def _circles() -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    graph, index, low, stack, found = _graph(), {}, {}, [], []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        for target in graph[module]:
            if target not in index:
                visit(target)
                low[module] = min(low[module], low[target])
            elif target in stack:
                low[module] = min(low[module], index[target])
        if low[module] == index[module]:
            component = []
            while not component or component[-1] != module:
                component.append(stack.pop())
            if len(component) > 1:
                found.append(sorted(component))

    for module in graph:
        if module not in index:
            visit(module)
    return found


def _engine_of(module: str) -> str | None:
    """'sb3' for engines.sb3 and its modules; None outside an engine's package (the
    contract's modules, engines.base and engines.untrusted, serve every engine)."""
    parts = module.split(".")
    shared = ("base", "untrusted")
    return parts[1] if len(parts) > 1 and parts[0] == "engines" and parts[1] not in shared else None


def test_every_module_has_one_layer() -> None:
    listed = [module for layer in _layer_list() for module in layer]
    assert len(_layer_list()) == 6
    assert sorted(listed) == sorted(cli_modules()), "list each composer.cli module in one layer"


def test_imports_go_down_the_layers_whatever_their_kind() -> None:
    layers = _layers()
    upward = [
        f"{module} (layer {layers[module]}) imports {target} (layer {layers[target]})"
        for module, targets in _graph().items()
        for target in targets
        if layers[target] > layers[module]
    ]
    assert upward == []


def test_no_circle_of_imports() -> None:
    assert _circles() == []


def test_an_engine_is_imported_only_by_itself_and_the_registry() -> None:
    problems = []
    for module, targets in _graph().items():
        for target in targets:
            engine = _engine_of(target)
            if engine is not None and module != "engines" and _engine_of(module) != engine:
                problems.append(f"{module} imports {target}, of the {engine} engine")
    assert problems == []


def test_only_engines_import_the_engines_libraries() -> None:
    problems = [
        f"{module}:{line} imports {name}"
        for module, name, where, line in _imports()
        if where != "string"
        and _engine_of(module) is None
        and any(name == lib or name.startswith(f"{lib}.") for lib in ENGINE_LIBRARIES)
    ]
    assert problems == []


def test_no_module_imports_the_shipped_tasks() -> None:
    importing = [
        f"{module}:{line} imports {name}"
        for module, name, where, line in _imports()
        if where != "string" and (name == "tasks" or name.startswith("tasks."))
    ]
    assert importing == []


def test_the_check_sees_what_it_should() -> None:
    """The checks above find what they look for: a registry entry by name, an import
    inside a function, one for type checks, and the engines' own library imports."""
    kinds = {(module, _resolve(name), where) for module, name, where, _ in _imports()}
    assert ("engines", "engines.ray", "string") in kinds
    assert ("main", "train", "string") in kinds
    assert ("engines.sb3", "engines.sb3.training", "function") in kinds
    assert ("engines.sb3", "engines.sb3.files", "typing") in kinds
    libraries = {(module, name) for module, name, where, _ in _imports() if where != "string"}
    assert ("engines.sb3.training", "composer.sb3") in libraries
    assert ("engines.ray.algorithm", "composer.rllib") in libraries
    assert any(m == "engines.ray.policy" and n.startswith("ray.") for m, n in libraries)
    assert _engine_of("engines.ray.instance") == "ray" and _engine_of("engines.base") is None
    assert _layers()["main"] > _layers()["engines"] > _layers()["engines.sb3"]
