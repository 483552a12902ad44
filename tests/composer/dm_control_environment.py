"""dm_control's own composer `environment` module, from its published wheel, on our `mjcf`
and our observables: an oracle for tests of our Environment.

    with dm_control_environment.loaded(tmp_path) as reference:
        theirs = reference.Environment(task, ...)        # dm_control's Environment
        reference.Environment.step                       # its methods, for a subclass of ours

Its environment, observation updater, observation buffer and `rl.control` modules are
read from the wheel (`tests.dm_control_wheel`, fetched at test time; skips when it cannot
be) into a package of another name, their dm_control imports pointed at ours and at each
other; nothing of it is in the repository. Needs dm_env and absl (skips without them).
"""

from __future__ import annotations

import importlib
import sys
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType

import pytest

from tests import dm_control_wheel

PACKAGE = "dm_control_environment_reference"
_MODULES = {
    "dm_control/composer/environment.py": "environment.py",
    "dm_control/composer/observation/updater.py": "updater.py",
    "dm_control/composer/observation/obs_buffer.py": "obs_buffer.py",
    "dm_control/rl/control.py": "control.py",
}
_IMPORTS = (
    ("from dm_control import mjcf", "import mjcf"),
    ("from dm_control.composer import variation", "from composer import variation"),
    (
        "from dm_control.composer.observation import obs_buffer",
        f"from {PACKAGE} import obs_buffer",
    ),
    (
        "from dm_control.composer import observation",
        f"from {PACKAGE} import updater as observation",
    ),
    ("from dm_control.rl import control", f"from {PACKAGE} import control"),
)


@contextmanager
def loaded(root: Path) -> Iterator[ModuleType]:
    """dm_control's `composer.environment` module, written under `root` and imported;
    removed from `sys.path` and `sys.modules` afterwards."""
    pytest.importorskip("dm_env")
    pytest.importorskip("absl")
    package = root / PACKAGE
    package.mkdir()
    (package / "__init__.py").write_text("")
    with zipfile.ZipFile(dm_control_wheel.wheel()) as archive:
        for name, target in _MODULES.items():
            source = archive.read(name).decode()
            for old, new in _IMPORTS:
                source = source.replace(old, new)
            (package / target).write_text(source)
    sys.path.insert(0, str(root))
    try:
        yield importlib.import_module(f"{PACKAGE}.environment")
    finally:
        sys.path.remove(str(root))
        for name in [n for n in sys.modules if n.startswith(PACKAGE)]:
            del sys.modules[name]
