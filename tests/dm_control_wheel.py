"""dm_control's published wheel, fetched at test time, with its imports rewritten to ours.

    root = dm_control_wheel.rewritten()          # pytest.skip when the index is unreachable
    outcomes = dm_control_wheel.run_unittest_file("composer/entity_test.py")
    module = dm_control_wheel.import_module("dm_control.locomotion.walkers.ant")
    archive = dm_control_wheel.wheel()           # the unchanged wheel file
    archive = dm_control_wheel.fetch()           # the same outside pytest (the benchmarks)

How dm_control's own code and tests are measured against ours: the wheel of
`dm-control==VERSION` is downloaded from the package index (`pip download --no-deps`,
nothing installed) into a cache outside the repository, unpacked, and every source file is
rewritten so that `from dm_control import mjcf` / `composer` and `from dm_control.mjcf...`
/ `dm_control.composer...` import our packages, and `from dm_control.utils import rewards`
/ `transformations` / `inverse_kinematics` ours in `composer.utils`. dm_control's own
implementation of `mjcf`, `composer` and those three modules is deleted from the rewritten
tree, so a reference the rewrite missed fails loudly instead of running their code; what
stays there are their tests, the modules those tests share (`hooks_test_utils`,
`fake_physics`, `code_for_debugging_test`), data files, and everything else (`locomotion`,
`manipulation`, `entities`, the other `utils`, `mujoco` ...), which then runs on ours.
A few test files get a rewrite of their own (`_FILE_REWRITES`): dm_control's inverse
kinematics test builds `dm_control.mujoco.Physics`, which does not load on MuJoCo 4, and
builds ours instead.

Nothing of it is copied into the repository: the cache is `$COMPOSER_TEST_CACHE` or the
system's temporary folder. Processes (pytest-xdist workers) share it under a file lock.

Native packages dm_control imports at module level for features the tests leave alone
(`labmaze`, for mazes, imported by `dm_control.locomotion.arenas`) are stood in for when
they are not installed: importing works, and using them raises ModuleNotFoundError.
"""

from __future__ import annotations

import hashlib
import importlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType
from typing import Any, NoReturn

VERSION = "1.0.50"
_OURS = ("mjcf", "composer")
# dm_control.utils modules that are ours in composer.utils.
_UTILS = ("rewards", "transformations", "inverse_kinematics")
# Edits of single files (under dm_control/), made before the import rewriting; each must
# find its text, so that a new wheel that changed it fails loudly.
_FILE_REWRITES = {
    "utils/inverse_kinematics_test.py": [
        ("from dm_control import mujoco\n", "import mjcf as mujoco  # mjcf.Physics\n"),
    ],
}
# Modules of dm_control's mjcf/composer that its tests import and that are not part of the
# implementation: kept (rewritten), and imported under their dm_control names.
_SUPPORT = re.compile(r"(_test|test_utils|fake_physics)$")
_FROM_TOP = re.compile(r"^(?P<indent>[ \t]*)from dm_control import (?P<names>[^(\n]+)$", re.M)
_FROM_SUB = re.compile(
    r"^(?P<indent>[ \t]*)from dm_control\.(?P<package>mjcf|composer)(?P<rest>(?:\.\w+)*)"
    r" import (?P<names>[^(\n]+)$",
    re.M,
)
_IMPORT_SUB = re.compile(
    r"^(?P<indent>[ \t]*)import dm_control\.(?P<module>(?:mjcf|composer)\S*)", re.M
)
_FROM_UTILS = re.compile(
    r"^(?P<indent>[ \t]*)from dm_control\.utils(?P<module>\.\w+)? import (?P<names>[^(\n]+)$",
    re.M,
)


def _cache() -> Path:
    base = os.environ.get("COMPOSER_TEST_CACHE") or tempfile.gettempdir()
    return Path(base) / f"mujoco-composer-dm_control-{VERSION}"


@contextmanager
def _locked(path: Path) -> Iterator[None]:
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as handle:
        try:
            import fcntl
        except ImportError:  # no fcntl (Windows): one process at a time is the caller's care
            yield
            return
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def _is_support(module: str) -> bool:
    """Whether dm_control module `module` (dotted, under mjcf or composer) is one kept."""
    return bool(_SUPPORT.search(module.rsplit(".", 1)[-1]))


def _split_names(names: str) -> list[tuple[str, str]]:
    """'a, b as c' -> [('a', 'a'), ('b', 'c')] (the imported name and the bound one)."""
    found = []
    for part in names.split("#", 1)[0].split(","):
        words = part.split()
        if words:
            found.append((words[0], words[-1]))
    return found


def _as_clause(name: str, bound: str) -> str:
    return name if name == bound else f"{name} as {bound}"


def rewrite(source: str) -> str:
    """`source` with its imports of dm_control's mjcf, composer and the utils of `_UTILS`
    turned into ours."""

    def top(match: re.Match[str]) -> str:
        indent, statements = match["indent"], []
        kept = []
        for name, bound in _split_names(match["names"]):
            if name in _OURS:
                statements.append(f"import {_as_clause(name, bound)}")
            else:
                kept.append(_as_clause(name, bound))
        if kept:
            statements.append(f"from dm_control import {', '.join(kept)}")
        return indent + "; ".join(statements)

    def sub(match: re.Match[str]) -> str:
        indent, module = match["indent"], match["package"] + match["rest"]
        if _is_support(module):
            return match[0]
        ours, theirs = [], []
        for name, bound in _split_names(match["names"]):
            (theirs if _is_support(f"{module}.{name}") else ours).append(_as_clause(name, bound))
        statements = []
        if ours:
            statements.append(f"from {module} import {', '.join(ours)}")
        if theirs:
            statements.append(f"from dm_control.{module} import {', '.join(theirs)}")
        return indent + "; ".join(statements)

    def plain(match: re.Match[str]) -> str:
        return f"{match['indent']}import {match['module']}"

    def utils(match: re.Match[str]) -> str:
        indent, module = match["indent"], (match["module"] or "")[1:]
        if module:  # from dm_control.utils.rewards import tolerance
            package = "composer.utils" if module in _UTILS else "dm_control.utils"
            return f"{indent}from {package}.{module} import {match['names']}"
        ours, theirs = [], []
        for name, bound in _split_names(match["names"]):
            (ours if name in _UTILS else theirs).append(_as_clause(name, bound))
        statements = []
        if ours:
            statements.append(f"from composer.utils import {', '.join(ours)}")
        if theirs:
            statements.append(f"from dm_control.utils import {', '.join(theirs)}")
        return indent + "; ".join(statements)

    source = re.sub(r"^([ \t]*)import mock$", r"\1from unittest import mock", source, flags=re.M)
    source = _FROM_TOP.sub(top, source)
    source = _FROM_SUB.sub(sub, source)
    source = _FROM_UTILS.sub(utils, source)
    return _IMPORT_SUB.sub(plain, source)


class Unavailable(RuntimeError):
    """The wheel is not in the cache and the package index could not give it."""


def _skip_unavailable(error: Unavailable) -> NoReturn:
    import pytest  # only tests skip; the benchmarks use `fetch` without pytest

    pytest.skip(str(error))


def _download(folder: Path) -> Path:
    wheels = sorted(folder.glob(f"dm_control-{VERSION}-*.whl"))
    if wheels:
        return wheels[0]
    result = subprocess.run(
        [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:",
         "--disable-pip-version-check", f"dm-control=={VERSION}", "-d", str(folder)],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    wheels = sorted(folder.glob(f"dm_control-{VERSION}-*.whl"))
    if result.returncode or not wheels:
        tail = (result.stderr or result.stdout).strip().splitlines()[-1:] or ["no output"]
        raise Unavailable(
            f"dm-control {VERSION} could not be fetched from the package index: {tail[0]}"
        )
    return wheels[0]


def _unpack(wheel: Path, target: Path) -> None:
    staging = target.with_name(target.name + ".partial")
    shutil.rmtree(staging, ignore_errors=True)
    with zipfile.ZipFile(wheel) as archive:
        archive.extractall(staging)
    package = staging / "dm_control"
    for name in _OURS:
        for path in sorted((package / name).rglob("*.py")):
            relative = path.relative_to(package).with_suffix("")
            if path.name == "__init__.py":
                path.write_text("")  # a plain namespace for the kept modules
            elif not _is_support(".".join(relative.parts)):
                path.unlink()  # their implementation: ours replaces it
    for name in _UTILS:
        (package / "utils" / f"{name}.py").unlink()
    for path in package.rglob("*.py"):
        original = text = path.read_text(encoding="utf-8")
        for old, new in _FILE_REWRITES.get(path.relative_to(package).as_posix(), []):
            if old not in text:
                raise RuntimeError(f"{path}: {old!r} not found; update _FILE_REWRITES")
            text = text.replace(old, new)
        rewritten = rewrite(text)
        if rewritten != original:
            path.write_text(rewritten, encoding="utf-8")
    os.replace(staging, target)


def fetch() -> Path:
    """The downloaded wheel file itself, unchanged, in the cache (downloaded on first use).
    Raises Unavailable when it is not cached and the index cannot be reached."""
    cache = _cache()
    with _locked(cache / "lock"):
        return _download(cache)


def wheel() -> Path:
    """`fetch()` for a test (dm_control's own implementation, e.g. as the reference of a
    differential test). Skips like `rewritten`."""
    try:
        return fetch()
    except Unavailable as error:
        _skip_unavailable(error)


_OPTIONAL_NATIVE = ("labmaze",)


class _AbsentMeta(type):
    """What a missing package's names are: classes one can subclass (dm_control's mazes
    subclass `labmaze.BaseMaze`) whose attributes are more of them, and calling one, or
    making an instance, raises."""

    def __getattr__(cls, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return _AbsentMeta(f"{cls.__name__}.{name}", (), {})

    def __call__(cls, *args: Any, **kwargs: Any) -> Any:
        raise ModuleNotFoundError(
            f"{cls.__name__.split('.')[0]} is not installed: dm_control needs it for this"
        )


class _Absent(ModuleType):
    """A stand-in for a native package that is not installed (see `_AbsentMeta`)."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return _AbsentMeta(f"{self.__name__}.{name}", (), {})


def _stand_in_for_absent_native_packages() -> None:
    for name in _OPTIONAL_NATIVE:
        if name in sys.modules:
            continue
        try:
            importlib.import_module(name)
        except ImportError:
            sys.modules[name] = _Absent(name)


def rewritten() -> Path:
    """The folder holding the rewritten `dm_control` package (on `sys.path` after this
    call). Skips the calling test when the wheel cannot be fetched."""
    cache = _cache()
    # Named by this file's contents: a change of the rewriting rules rewrites the tree anew.
    digest = hashlib.sha1(Path(__file__).read_bytes()).hexdigest()[:12]
    target = cache / f"rewritten-{digest}"
    if not (target / "dm_control").is_dir():
        with _locked(cache / "lock"):
            if not (target / "dm_control").is_dir():
                try:
                    _unpack(_download(cache), target)
                except Unavailable as error:
                    _skip_unavailable(error)
    if str(target) not in sys.path:
        sys.path.insert(0, str(target))
    _stand_in_for_absent_native_packages()
    return target


@contextmanager
def _mujoco_warnings_kept() -> Iterator[None]:
    """Run dm_control's code, then give MuJoCo back the warning handler it had: importing
    `dm_control.mujoco` installs its own, process-wide, which would route every later
    test's MuJoCo warnings to absl instead of mjcf's logger."""
    import mujoco

    handler = mujoco.get_mju_user_warning()
    try:
        yield
    finally:
        mujoco.set_mju_user_warning(handler)


def import_module(name: str) -> ModuleType:
    """Import `name` (a dm_control module, e.g. 'dm_control.locomotion.walkers.ant') from
    the rewritten wheel; skips like `rewritten`."""
    rewritten()
    with _mujoco_warnings_kept():
        return importlib.import_module(name)


class _Outcomes(unittest.TestResult):
    def __init__(self) -> None:
        super().__init__()
        self.outcomes: dict[str, str] = {}

    @staticmethod
    def _name(test: unittest.TestCase) -> str:
        if not isinstance(test, unittest.TestCase):  # a failed setUpClass or module fixture
            return str(test)
        return f"{type(test).__name__}.{test._testMethodName}"

    def addSuccess(self, test: unittest.TestCase) -> None:
        self.outcomes[self._name(test)] = "passed"

    def addFailure(self, test: unittest.TestCase, err: object) -> None:
        self.outcomes[self._name(test)] = "failed: " + self._exc_info_to_string(err, test)

    def addError(self, test: unittest.TestCase, err: object) -> None:
        self.outcomes[self._name(test)] = "error: " + self._exc_info_to_string(err, test)

    def addSkip(self, test: unittest.TestCase, reason: str) -> None:
        self.outcomes[self._name(test)] = f"skipped: {reason}"

    def addExpectedFailure(self, test: unittest.TestCase, err: object) -> None:
        self.outcomes[self._name(test)] = "passed"

    def addUnexpectedSuccess(self, test: unittest.TestCase) -> None:
        self.outcomes[self._name(test)] = "failed: unexpected success"


def run_unittest_file(relative: str, class_fixtures: bool = True) -> dict[str, str]:
    """Run dm_control's test file `relative` (e.g. 'composer/entity_test.py', under
    dm_control/) in this process; each test's outcome by 'Class.method': 'passed', or
    'failed: ...', 'error: ...', 'skipped: ...' with the traceback or reason. A file that
    does not import is one outcome, 'import' -> 'error: ...'. With `class_fixtures`
    False, each test runs alone, without its class's and module's setUpClass and
    setUpModule (for files whose class fixture reaches into dm_control internals that
    only some of its tests use)."""
    rewritten()
    from absl import flags

    if not flags.FLAGS.is_parsed():
        flags.FLAGS.mark_as_parsed()
    name = "dm_control." + relative.removesuffix(".py").replace("/", ".")
    with _mujoco_warnings_kept():
        return _run_module(name, class_fixtures)


def _run_module(name: str, class_fixtures: bool) -> dict[str, str]:
    try:
        module = importlib.import_module(name)
    except Exception as e:  # what is missing on our side shows here first
        return {"import": f"error: {type(e).__name__}: {e}"}
    suite = unittest.defaultTestLoader.loadTestsFromModule(module)
    result = _Outcomes()
    if class_fixtures:
        suite.run(result)
    else:
        for test in _tests_of(suite):
            test.run(result)  # a TestCase run alone skips class and module fixtures
    return result.outcomes


def _tests_of(suite: unittest.TestSuite) -> Iterator[unittest.TestCase]:
    for item in suite:
        if isinstance(item, unittest.TestSuite):
            yield from _tests_of(item)
        else:
            yield item
