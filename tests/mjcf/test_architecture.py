"""The architecture of `mjcf`, checked on its real source (ast, tests/imports.py), so that
it cannot drift silently (docs/architecture.md describes it):

- every module is in one layer's folder (`mjcf/schema`, `mjcf/tree`, `mjcf/compose`,
  `mjcf/io`, `mjcf/sim`, bottom to top), but the package's front door: `mjcf/__init__`,
  `mjcf/errors` (the exceptions every layer raises) and dm_control's module paths
  (`mjcf.element`, `mjcf.physics` ...), short re-exports that no layer imports;
- a module imports only from its own layer and the layers below it, and no import circle
  joins mjcf's modules;
- a module calls a layer above it only through `mjcf.tree.above`, the one module that
  imports inside functions, each of its functions naming the one it calls;
- a private member of an object of another module is used only as the internal protocol
  of its class allows: by the modules it names, and changed only by those it lets.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator

from tests import imports

LAYERS = ("schema", "tree", "compose", "io", "sim")  # bottom to top
FOUNDATION = "mjcf.errors"
LATE_IMPORTS = "mjcf.tree.above"  # the one module that imports inside functions
# dm_control's module paths: short re-exports of the layers' names, for user code only.
DM_CONTROL_PATHS = frozenset(
    f"mjcf.{name}"
    for name in (
        "base", "constants", "debugging", "element", "namescope", "parser", "physics",
        "traversal_utils",
    )
)  # fmt: skip

# At most this many uses of a private member of another module's object (`element._attrs`
# outside `mjcf.tree.element`): each module keeps its objects' state, and others ask it.
MOST_PRIVATE_REACHES = 30
# The modules that use private members of other modules' objects: those members, whether
# they may change them, and why. No other module does.
REACHING: dict[str, tuple[frozenset[str], bool, str]] = {
    "builder": (
        frozenset({"_make", "_attrs", "_children", "_register", "_unregister_subtree",
                   "_implicit", "_keep", "_cut", "_defer", "_source", "_text"}),
        True,
        "the one module, but mjcf.tree.element itself, that writes an element's slots",
    ),
    "serializer": (
        frozenset({"_text", "_spec", "_attrs", "_children"}),
        False,
        "its per-element loop reads the slots: a reading function's call each would cost "
        "a fifth of writing an unchanged model (bench parse: write_ms)",
    ),
    "element": (
        frozenset({"_version", "_register"}),
        True,
        "counts each change of an element in its model's version, on every set; records a "
        "new child's name (`_register`: mjcf.tree.element_names, a part of Element)",
    ),
    "element_names": (
        frozenset({"_children"}),
        False,
        "a part of Element: checks a name kept within its parent against the parent's "
        "other children",
    ),
    "namescope": (
        frozenset({"_resolve"}),
        False,
        "asks its model to build the element of a name read but not built yet",
    ),
    "references": (
        frozenset({"_references", "_attrs"}),
        False,
        "keeps its state of a model on the model; pins text references in place",
    ),
    "assets": (
        frozenset({"_confine_to"}),
        False,
        "reads the folder `strict_paths` confines a model's files to (set by the reader)",
    ),
    "frame_poses": (
        frozenset({"_frame_poses"}),
        True,
        "keeps the frame poses of a physics' current model on the physics",
    ),
    "validity": (
        frozenset({"_raise_if_invalid"}),
        False,
        "asks the physics to raise if its state is invalid, after a checked block",
    ),
}  # fmt: skip
_MUTATORS = frozenset(
    {"add", "append", "clear", "discard", "extend", "insert", "pop", "remove", "setdefault",
     "sort", "update"}
)  # fmt: skip


class _File:
    """One source file: its text and syntax tree."""

    def __init__(self, module: str) -> None:
        self.tree, lines = imports.syntax(imports.modules("mjcf")[module])
        self.lines = lines

    def line(self, lineno: int) -> str:
        return self.lines[lineno - 1]


def _layer(module: str) -> int | None:
    """The index of a module's layer in LAYERS; None for the front door."""
    parts = module.split(".")
    return LAYERS.index(parts[1]) if len(parts) > 2 and parts[1] in LAYERS else None


@functools.cache
def _modules() -> dict[str, list[_File]]:
    """{module's short name: its files}: each module of the layers (the schema package's
    `__init__` as `schema`), for the check of private members."""
    found: dict[str, list[_File]] = {}
    for module in imports.modules("mjcf"):
        if module.count(".") < 2 and module != "mjcf.schema":
            continue  # the front door, the foundation and the layers' empty __init__s
        found.setdefault(module.rsplit(".", 1)[-1], []).append(_File(module))
    return found


def test_every_module_is_in_a_layer_or_the_front_door() -> None:
    known = imports.modules("mjcf")
    top = {m for m in known if m.count(".") == 1}
    layer_packages = {f"mjcf.{layer}" for layer in LAYERS}
    assert top - layer_packages == DM_CONTROL_PATHS | {FOUNDATION}
    assert all(_layer(m) is not None for m in known if m.count(".") > 1)


def test_dm_control_paths_only_re_export() -> None:
    """dm_control's module paths define nothing but names bound to what the layers define
    (and constants), and are short."""
    for module in DM_CONTROL_PATHS:
        tree, lines = imports.syntax(imports.modules("mjcf")[module])
        defined = [n for n in tree.body if isinstance(n, ast.FunctionDef | ast.ClassDef)]
        assert defined == [], module
        assert len(lines) <= 50, module


def test_imports_go_down_the_layers() -> None:
    known = imports.modules("mjcf")
    upward = []
    for statement in imports.imports("mjcf"):
        layer = _layer(statement.module)
        if layer is None or statement.where == "typing" or statement.module == LATE_IMPORTS:
            continue  # the late imports: see the next test
        for target in statement.targets(known):
            if not target.startswith("mjcf") or target == FOUNDATION:
                continue
            target_layer = _layer(target)
            if target_layer is None and target != f"mjcf.{LAYERS[layer]}":
                if target not in [f"mjcf.{name}" for name in LAYERS]:
                    upward.append(f"{statement}: imports the front door {target}")
            elif target_layer is not None and target_layer > layer:
                upward.append(f"{statement}: imports {target}, a layer above")
    assert upward == []


def test_no_import_circle_at_module_level() -> None:
    assert imports.circles(imports.graph("mjcf", deferred=False)) == []


def _reaches(graph: dict[str, frozenset[str]], start: str, goal: str) -> bool:
    seen, stack = set(), [start]
    while stack:
        module = stack.pop()
        if module == goal:
            return True
        if module not in seen:
            seen.add(module)
            stack.extend(graph.get(module, ()))
    return False


def test_only_the_late_import_module_imports_inside_functions() -> None:
    """`mjcf.tree.above` is where a layer calls the layers above it: each of its functions
    imports one function of a module above the tree and calls it. No other module imports
    inside a function (a reader follows every other call by its module-level import)."""
    known = imports.modules("mjcf")
    problems = []
    for statement in imports.imports("mjcf"):
        if statement.where != "function":
            continue
        if statement.module != LATE_IMPORTS:
            problems.append(f"{statement}: import it at the top (or call through {LATE_IMPORTS})")
            continue
        for target in statement.targets(known):
            layer = _layer(target)
            if layer is None or layer <= LAYERS.index("tree"):
                problems.append(f"{statement}: {target} is no layer above the tree")
    assert problems == []
    tree, _ = imports.syntax(known[LATE_IMPORTS])
    for function in tree.body:
        if isinstance(function, ast.FunctionDef):
            code = [n for n in function.body if not isinstance(n, ast.Expr | ast.Return)]
            assert len(code) == 1 and isinstance(code[0], ast.ImportFrom), function.name
            assert len(function.body) == 3, f"{function.name}: a docstring, an import, a call"


def test_private_members_of_other_modules_are_few_and_listed() -> None:
    uses = list(_private_uses())
    assert len(uses) <= MOST_PRIVATE_REACHES
    problems = []
    for module, name, changes, lineno in uses:
        members, may_change, _ = REACHING.get(module, (frozenset(), False, ""))
        where = f"{module}:{lineno}: {name}"
        if name not in members:
            problems.append(f"{where} belongs to another module: ask that module")
        elif changes and not may_change:
            problems.append(f"{where}: {module} only reads it")
    assert problems == []


def test_the_check_sees_what_it_should() -> None:
    """The checks above find what they look for: a real cross-module access and an upward
    import would be reported, and so would a circle."""
    uses = {(module, name) for module, name, _, _ in _private_uses()}
    assert {
        ("serializer", "_text"),
        ("builder", "_attrs"),
        ("validity", "_raise_if_invalid"),
    } <= uses
    assert ("binding", "_stale") not in uses  # the protocol binding defines
    graph = imports.graph("mjcf", deferred=True)
    assert _reaches(graph, "mjcf.io.serializer", "mjcf.tree.assets")
    assert "mjcf.compose.attachment" in graph["mjcf.compose.copying"]
    assert "mjcf.tree.element" in graph["mjcf.tree.root"]
    element, attachment = "mjcf.tree.element", "mjcf.compose.attachment"
    looped = {**graph, element: graph[element] | {attachment}}
    assert any({element, attachment, "mjcf.tree.root"} <= set(c) for c in imports.circles(looped))
    assert _layer("mjcf.sim.physics") > _layer("mjcf.tree.element")  # type: ignore[operator]
    assert "mjcf.tree.element" in graph["mjcf.sim.physics"]


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


def _parents(tree: ast.AST) -> dict[ast.AST, ast.AST]:
    return {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}


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
