"""What of mjcf's schema a user's program gets: `mjcf.schema` and its JSON, in the wheel
and at runtime; the build-time generator and checker (tools/mjcf_schema) stay in the
repository, and nothing installed imports them."""

from __future__ import annotations

import ast
import json
import subprocess
import sys
import zipfile
from pathlib import Path

from mjcf import schema
from tests.conftest import INSTALLED_PACKAGES, REPO, gym_model

# The schema, the refusals applied on top of it when it loads (what crashes MuJoCo), and
# the attribute values it is made of, with their arrays and messages' suggestions (the
# bottom layer of mjcf).
RUNTIME_SCHEMA = {
    "mjcf/schema/__init__.py", "mjcf/schema/_refusals.py", "mjcf/schema/mjcf_schema.json",
    "mjcf/schema/values.py", "mjcf/schema/tracked_array.py", "mjcf/schema/suggestions.py",
}  # fmt: skip


def test_the_wheel_carries_the_runtime_schema_and_none_of_its_tooling(built_wheel: Path) -> None:
    with zipfile.ZipFile(built_wheel) as archive:
        names = archive.namelist()
        shipped_json = archive.read("mjcf/schema/mjcf_schema.json")
    assert {name for name in names if name.startswith("mjcf/schema/")} == RUNTIME_SCHEMA
    assert shipped_json == schema.DATA_FILE.read_bytes()
    # Every runtime module of mjcf is in the wheel, and nothing but them.
    runtime = {
        str(path.relative_to(REPO)) for path in (REPO / "mjcf").rglob("*")
        if path.is_file() and "__pycache__" not in path.parts
    }  # fmt: skip
    assert {name for name in names if name.startswith("mjcf/")} == runtime
    tops = {name.split("/")[0] for name in names}
    assert {top for top in tops if not top.endswith(".dist-info")} == set(INSTALLED_PACKAGES)


def _imports_of_tools(path: Path) -> list[str]:
    """'file:line' of each import of the tools package in a source file."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            modules = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and not node.level:
            modules = [node.module or ""]
        else:
            continue
        if any(module == "tools" or module.startswith("tools.") for module in modules):
            found.append(f"{path.relative_to(REPO)}:{node.lineno}")
    return found


def test_no_installed_module_imports_the_tooling_even_inside_a_function() -> None:
    importers = [
        where
        for package in INSTALLED_PACKAGES
        for path in sorted((REPO / package).rglob("*.py"))
        for where in _imports_of_tools(path)
    ]
    assert importers == []
    # The scan finds such imports where they are: the generator imports its own modules.
    assert _imports_of_tools(REPO / "tools" / "mjcf_schema" / "generate.py")


# Uses every installed package and mjcf's schema on a real model, then lists the tooling's
# modules in sys.modules; then imports the tooling itself, to show that the listing sees it.
_USE_AND_LIST = """
import json, sys
import arenas, composer, entities, mjcf, tasks

def tooling():
    return sorted(name for name in sys.modules if name.split(".")[0] == "tools")

model = mjcf.from_path(sys.argv[1])
model.worldbody.add("geom", name="probe_geom", size=[0.1])
physics = mjcf.Physics.from_mjcf_model(model)
physics.step()
used = tooling()
from tools.mjcf_schema import check, generate
print(json.dumps({"used": used, "then": tooling(), "nbody": int(physics.model.nbody)}))
"""


def test_using_mjcf_imports_none_of_the_tooling() -> None:
    result = subprocess.run(
        [sys.executable, "-c", _USE_AND_LIST, str(gym_model("humanoid"))],
        cwd=REPO, capture_output=True, text=True, check=True,
    )  # fmt: skip
    seen = json.loads(result.stdout)
    assert seen["nbody"] > 10
    assert seen["used"] == []
    assert {"tools.mjcf_schema.check", "tools.mjcf_schema.generate"} <= set(seen["then"])
