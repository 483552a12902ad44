"""The architecture of `mjcf`, checked on its real source (ast), so that it cannot drift
silently (the package docstring describes it):

- module-level imports go down the layers the package docstring lists, never up;
- no import circle between mjcf's modules, neither at module level nor through imports
  inside functions: a lower layer calls up only through `mjcf.upcalls`, which the package
  fills when imported;
- an import inside a function is one that a module-level import would make circular,
  and it says so in a comment;
- a private member of an object of another module is used only as the internal protocol
  of its class allows: by the modules it names, and changed only by those it lets.
"""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Iterator
from pathlib import Path

import pytest

import mjcf
from mjcf import upcalls
from tests.composer.test_import_graph import _circles

PACKAGE = Path(mjcf.__file__).parent

ANY = None  # every mjcf module
# The modules that make elements and fill them (`_make`, `_attrs`, `_children`, `_register`):
# the reading functions are read-only views, and the public setters would check again, for
# every element, what a builder has checked (the parser: the whole document at once).
TREE_BUILDERS = frozenset(
    {"parser", "copying", "default_sections", "defaults", "attachment", "root", "global_settings"}
)
# The modules that read and write a physics' state for bindings and named access: every read
# tests `_stale` and calls `_refresh()` inline, the per-read path (bench bind), where a call
# more would cost; they read the raw MjModel and MjData through `model` and `data`.
SIMULATION = frozenset({"binding", "named", "frame_binding", "frame_poses"})
# A model's references state is `mjcf.references`' own, kept on the model (one reach, the
# state's only reader); the reader and copies set it up through that module's functions.
REFERENCES = frozenset({"references"})
# Element's bases and the tree modules below it, which `mjcf.element` imports: they cannot
# import its reading functions, and are part of what an element is.
BELOW_ELEMENT = frozenset({"element_names", "element_rules", "element_list", "references"})
# The writer's per-element loop reads the slots: the reading protocol's calls there cost a
# fifth of a write (bench parse: write_ms).
WRITER = frozenset({"serializer"})
# `mjcf.element` imports `mjcf.assets` (to read file attributes into Assets), which so cannot
# import the reading functions: it reads which of a mesh's attributes are set in `_attrs`.
IMPORTED_BY_ELEMENT = frozenset({"assets"})
# The internal protocols: private member -> (the class that documents it, the modules that
# may use it, the modules that may change it: assign it, or mutate what it holds).
PROTOCOL: dict[str, tuple[str, frozenset[str] | None, frozenset[str]]] = {
    "_spec": ("element.Element", WRITER, frozenset()),
    "_parent": ("element.Element", BELOW_ELEMENT, frozenset()),
    "_attrs": (
        "element.Element",
        TREE_BUILDERS | BELOW_ELEMENT | WRITER | IMPORTED_BY_ELEMENT,
        TREE_BUILDERS | {"references"},
    ),
    "_children": ("element.Element", TREE_BUILDERS | BELOW_ELEMENT | WRITER, TREE_BUILDERS),
    "_source": (
        "element.Element",
        frozenset({"parser", "copying"}),
        frozenset({"parser", "copying"}),
    ),
    "_implicit": ("element_names.ElementNames", TREE_BUILDERS, frozenset()),
    "_keep": ("element.Element", TREE_BUILDERS, frozenset()),
    "_make": ("element.Element", TREE_BUILDERS, frozenset()),
    "_register": ("element_names.ElementNames", TREE_BUILDERS | {"element"}, frozenset()),
    "_unregister_subtree": ("element_names.ElementNames", TREE_BUILDERS, frozenset()),
    "_cut": ("element.Element", TREE_BUILDERS, frozenset()),
    "_text": ("element.Element", frozenset({"serializer"}), frozenset({"serializer"})),
    "_xml": ("element.Element", frozenset({"namescope", "root"}), frozenset()),
    "_defer": ("element.Element", TREE_BUILDERS, frozenset()),
    "_resolve": ("root.RootElement", frozenset({"namescope"}), frozenset()),
    "_early": ("root.RootElement", frozenset({"element"}), frozenset({"element"})),
    "_child_built_from": ("element.Element", frozenset({"root"}), frozenset()),
    "_version": (
        "root.RootElement",
        frozenset({"element", "copying"}),
        frozenset({"element", "copying"}),
    ),
    "_frame": ("root.RootElement", frozenset({"attachment"}), frozenset({"attachment"})),
    "_attachments": ("root.RootElement", frozenset({"attachment"}), frozenset({"attachment"})),
    "_numbering": ("root.RootElement", frozenset({"naming"}), frozenset({"naming"})),
    "_composed": ("root.RootElement", frozenset({"composition"}), frozenset({"composition"})),
    "_confine_to": ("root.RootElement", frozenset({"assets", "parser"}), frozenset({"parser"})),
    "_references": ("root.RootElement", REFERENCES, frozenset()),
    "_before_name_change": ("root.RootElement", frozenset({"namescope"}), frozenset()),
    "_stale": ("physics.Physics", SIMULATION, frozenset({"binding"})),
    "_refresh": ("physics.Physics", SIMULATION, frozenset()),
    "_compute_on_demand": ("physics.Physics", SIMULATION, frozenset()),
    "_update_constants": ("physics.Physics", frozenset({"binding"}), frozenset()),
    "_live_bindings": ("physics.Physics", frozenset({"binding"}), frozenset({"binding"})),
    "_raise_if_invalid": ("physics.Physics", frozenset({"validity"}), frozenset()),
    "_frame_poses": ("physics.Physics", frozenset({"frame_poses"}), frozenset({"frame_poses"})),
    "_detach": ("binding.Binding", frozenset({"physics"}), frozenset()),
    "_refuse_writes": ("binding.Binding", frozenset({"physics"}), frozenset()),
    "_writeback": ("binding.WriteThrough", frozenset({"named"}), frozenset({"named"})),
}
_MUTATORS = frozenset(
    {"add", "append", "clear", "discard", "extend", "insert", "pop", "remove", "setdefault",
     "sort", "update"}
)  # fmt: skip


class _File:
    """One source file: its text and syntax tree."""

    def __init__(self, path: Path) -> None:
        self.text = path.read_text()
        self.tree = ast.parse(self.text, str(path))

    def line(self, lineno: int) -> str:
        return self.text.splitlines()[lineno - 1]


@functools.cache
def _modules() -> dict[str, list[_File]]:
    """{module name: its files}: each mjcf/*.py, and the schema package as one module."""
    found = {path.stem: [_File(path)] for path in PACKAGE.glob("*.py")}
    del found["__init__"]
    found["schema"] = [_File(path) for path in sorted((PACKAGE / "schema").glob("*.py"))]
    return found


def _layer_list() -> list[list[str]]:
    """The modules of each layer, as the package docstring lists them."""
    layers: list[list[str]] = []
    for line in (mjcf.__doc__ or "").splitlines():
        match = re.fullmatch(r" {4}(\w+):\s+([\w ]+)", line)
        if match:
            layers.append(match.group(2).split())
        elif layers and re.fullmatch(r" {6,}[\w ]+", line):
            layers[-1].extend(line.split())
    return layers


def _layers() -> dict[str, int]:
    """{module: its layer's index}."""
    return {module: index for index, modules in enumerate(_layer_list()) for module in modules}


def _parents(tree: ast.AST) -> dict[ast.AST, ast.AST]:
    return {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}


def _targets(node: ast.Import | ast.ImportFrom) -> list[str]:
    """The mjcf modules an import statement imports ('' for one outside mjcf)."""
    if isinstance(node, ast.ImportFrom):
        module = node.module or ""
        if node.level or not (module == "mjcf" or module.startswith("mjcf.")):
            return [""]
        if module == "mjcf":
            return [alias.name for alias in node.names]
        return [module.split(".")[1]]
    return [
        alias.name.split(".")[1] if alias.name.startswith("mjcf.") else "" for alias in node.names
    ]


def _imports() -> Iterator[tuple[str, str, str, ast.stmt, _File]]:
    """(module, imported mjcf module or '', 'top' | 'function', statement, file) for every
    import outside `if TYPE_CHECKING:` blocks."""
    for module, files in _modules().items():
        for file in files:
            parents = _parents(file.tree)
            for node in ast.walk(file.tree):
                if not isinstance(node, ast.Import | ast.ImportFrom):
                    continue
                where, parent = "top", parents.get(node)
                while parent is not None:
                    if isinstance(parent, ast.If) and "TYPE_CHECKING" in ast.unparse(parent.test):
                        where = "typing"
                    if isinstance(parent, ast.FunctionDef | ast.AsyncFunctionDef):
                        where = "function"
                    parent = parents.get(parent)
                if where != "typing":
                    for target in _targets(node):
                        if target != module:
                            yield module, target, where, node, file


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Module-level imports between mjcf modules."""
    graph: dict[str, set[str]] = {module: set() for module in _modules()}
    for module, target, where, _, _ in _imports():
        if where == "top" and target:
            graph[module].add(target)
    return graph


def _reaches(start: str, goal: str) -> bool:
    seen, stack = set(), [start]
    while stack:
        module = stack.pop()
        if module == goal:
            return True
        if module not in seen:
            seen.add(module)
            stack.extend(_graph().get(module, ()))
    return False


def test_every_module_has_one_layer() -> None:
    listed = [module for layer in _layer_list() for module in layer]
    assert len(_layer_list()) == 5
    assert sorted(listed) == sorted(_modules()), "list each mjcf module in one layer"


def test_module_level_imports_go_down_the_layers() -> None:
    layers = _layers()
    upward = [
        f"{module} (layer {layers[module]}) imports {target} (layer {layers[target]})"
        for module, targets in _graph().items()
        for target in targets
        if layers[target] > layers[module]
    ]
    assert upward == []


def test_imports_inside_functions_are_the_ones_a_cycle_forces() -> None:
    problems = []
    for module, target, where, node, file in _imports():
        if where != "function":
            continue
        if not target:
            problems.append(f"{module}:{node.lineno}: {ast.unparse(node)}: import it at the top")
        elif not _reaches(target, module):
            problems.append(f"{module}:{node.lineno}: {target} does not import {module}: no cycle")
        elif "# cycle: " not in file.line(node.lineno):
            problems.append(f"{module}:{node.lineno}: say which cycle ('# cycle: ...')")
    assert problems == []


def _runtime_graph(deferred: bool) -> dict[str, frozenset[str]]:
    """mjcf's module imports of each other at run time: at module level, and with
    `deferred` inside functions too."""
    graph: dict[str, set[str]] = {module: set() for module in _modules()}
    for module, target, where, _, _ in _imports():
        if not target:
            continue
        if where == "top" or (deferred and where == "function"):
            graph[module].add(target)
    return {module: frozenset(targets) for module, targets in graph.items()}


def test_no_import_circle_at_module_level() -> None:
    assert _circles(_runtime_graph(deferred=False)) == []


def test_no_import_circle_through_imports_inside_functions() -> None:
    assert _circles(_runtime_graph(deferred=True)) == []


def test_every_upcall_is_installed() -> None:
    """Every call the tree makes up (`mjcf.upcalls.Above`) has its function, the one its
    docstring names."""
    names = list(upcalls.Above.__annotations__)
    missing = [name for name in names if not hasattr(upcalls.ABOVE, name)]
    assert missing == []
    assert upcalls.ABOVE.find is mjcf.traversal.find
    assert upcalls.ABOVE.root_class is mjcf.RootElement
    assert all(f"`{name}`" in (upcalls.Above.__doc__ or "") for name in names)


def test_private_members_of_other_modules_are_used_through_their_protocol() -> None:
    problems = []
    for module, name, changes, lineno in _private_uses():
        protocol = PROTOCOL.get(name)
        where = f"{module}:{lineno}: {name}"
        if protocol is None:
            problems.append(f"{where} belongs to another module and to no internal protocol")
            continue
        _, users, changers = protocol
        if users is not ANY and module not in users:
            problems.append(f"{where}: the protocol does not let {module} use it")
        elif changes and module not in changers:
            problems.append(f"{where}: the protocol does not let {module} change it")
    assert problems == []


@pytest.mark.parametrize("name", sorted(PROTOCOL))
def test_protocol_members_are_documented_by_their_class(name: str) -> None:
    owner = PROTOCOL[name][0]
    module_name, class_name = owner.split(".")
    module = __import__(f"mjcf.{module_name}", fromlist=[class_name])
    cls = getattr(module, class_name)
    assert f"`{name}" in (cls.__doc__ or ""), f"{owner}'s docstring should describe {name}"
    assert name in _owned(_modules()[module_name]), f"{name} is not {module_name}'s"


def test_the_check_sees_what_it_should() -> None:
    """The checks above find what they look for: a real cross-module access and an upward
    import would be reported, and so would a circle."""
    uses = {(module, name) for module, name, _, _ in _private_uses()}
    assert {("serializer", "_text"), ("binding", "_stale"), ("copying", "_attrs")} <= uses
    assert _reaches("serializer", "assets")
    graph = _runtime_graph(deferred=True)
    assert "attachment" in graph["copying"] and "element" in graph["root"]
    looped = {**graph, "element": graph["element"] | {"attachment"}}
    assert any({"element", "attachment", "root"} <= set(circle) for circle in _circles(looped))
    assert _layers()["physics"] > _layers()["element"] and "element" in _graph()["physics"]


# -- helpers ------------------------------------------------------------------------------


def _owned(files: list[_File]) -> set[str]:
    """The private names a module defines: its module-level and class-level names
    (functions, classes, constants, slots) and the attributes its methods set on `self`."""
    owned: set[str] = set()
    for file in files:
        bodies = [file.tree.body]
        while bodies:
            for statement in bodies.pop():
                if isinstance(statement, ast.ClassDef):
                    bodies.append(statement.body)
                owned.update(_defined(statement))
        owned.update(
            node.attr
            for node in ast.walk(file.tree)
            if isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Store)
            and isinstance(node.value, ast.Name)
            and node.value.id in ("self", "cls")
        )
    return {name for name in owned if name.startswith("_")}


def _defined(statement: ast.stmt) -> set[str]:
    """The names a module- or class-level statement defines (a `__slots__` its slots)."""
    if isinstance(statement, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
        return {statement.name}
    targets = []
    if isinstance(statement, ast.Assign):
        targets = statement.targets
    elif isinstance(statement, ast.AnnAssign):
        targets = [statement.target]
    names = {t.id for target in targets for t in ast.walk(target) if isinstance(t, ast.Name)}
    if "__slots__" in names and isinstance(statement, ast.Assign):
        names |= {
            c.value
            for c in ast.walk(statement.value)
            if isinstance(c, ast.Constant) and isinstance(c.value, str)
        }
    return names


def _foreign_names(tree: ast.Module) -> set[str]:
    """Names bound to modules and objects imported from outside mjcf (lxml's etree, sys)."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(
                (a.asname or a.name).split(".")[0]
                for a in node.names
                if not a.name.startswith("mjcf")
            )
        elif isinstance(node, ast.ImportFrom) and not (node.module or "").startswith("mjcf"):
            names.update(a.asname or a.name for a in node.names)
    return names


def _private_uses() -> Iterator[tuple[str, str, bool, int]]:
    """(module, private name, whether it changes it, line) for every use of a private
    member, not its own, on an object other than `self`/`cls`."""
    for module, files in _modules().items():
        owned = _owned(files)
        for file in files:
            foreign = _foreign_names(file.tree)
            parents = _parents(file.tree)
            for node in ast.walk(file.tree):
                found = _private_use(node, parents, foreign)
                if found is not None and found[0] not in owned:
                    yield module, found[0], found[1], node.lineno


def _private_use(
    node: ast.AST, parents: dict[ast.AST, ast.AST], foreign: set[str]
) -> tuple[str, bool] | None:
    if isinstance(node, ast.Call) and len(node.args) >= 2:
        function = ast.unparse(node.func)
        name, target = node.args[1], node.args[0]
        on_self = isinstance(target, ast.Name) and target.id in ("self", "cls")
        if function in ("object.__setattr__", "setter") and isinstance(name, ast.Constant):
            return None if on_self else (str(name.value), True)
        return None
    if not isinstance(node, ast.Attribute) or not _is_private(node.attr):
        return None
    base = node.value
    if isinstance(base, ast.Name) and (base.id in ("self", "cls") or base.id in foreign):
        return None
    parent = parents.get(node)
    changes = isinstance(node.ctx, ast.Store | ast.Del) or (
        isinstance(parent, ast.Subscript) and isinstance(parent.ctx, ast.Store | ast.Del)
    )
    if isinstance(parent, ast.Attribute) and parent.attr in _MUTATORS:
        changes = changes or isinstance(parents.get(parent), ast.Call)
    return node.attr, changes


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")
