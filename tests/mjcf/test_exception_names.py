"""Exception names: none shadows a Python builtin, each still is the builtin a dm_control
user catches, and the previous release's names work with a DeprecationWarning."""

import builtins
import importlib

import pytest

import mjcf

RENAMED = {
    "NameError": ("NameClashError", ValueError),
    "AttributeError": ("UnknownAttributeError", AttributeError),
    "ReferenceError": ("InvalidReferenceError", ValueError),
}


@pytest.mark.parametrize("package", ["mjcf", "composer", "entities", "arenas", "tasks"])
def test_star_import_shadows_no_builtin(package: str) -> None:
    namespace: dict[str, object] = {}
    exec(f"from {package} import *", namespace)
    shadowed = sorted(set(namespace) & set(dir(builtins)) - {"__builtins__"})
    assert shadowed == []
    assert set(importlib.import_module(package).__all__) <= set(namespace)


@pytest.mark.parametrize("old", sorted(RENAMED))
def test_old_names_are_deprecated_aliases(old: str) -> None:
    new, builtin = RENAMED[old]
    renamed = getattr(mjcf, new)
    assert issubclass(renamed, mjcf.Error) and issubclass(renamed, builtin)
    assert old not in mjcf.__all__ and new in mjcf.__all__
    with pytest.warns(DeprecationWarning, match=f"mjcf.{old} is now mjcf.{new}") as caught:
        alias = getattr(mjcf, old)
    assert alias is renamed
    assert caught[0].filename == __file__  # the warning points at the user's line
    with pytest.warns(DeprecationWarning, match=f"mjcf.errors.{old} is now"):
        assert getattr(mjcf.errors, old) is renamed


def test_unknown_names_are_still_attribute_errors() -> None:
    with pytest.raises(AttributeError, match="module 'mjcf' has no attribute 'NoSuchError'"):
        _ = mjcf.NoSuchError
    assert not hasattr(mjcf.errors, "TypeError")


def test_the_new_names_are_what_is_raised() -> None:
    model = mjcf.RootElement()
    body = model.worldbody.add("body", name="arm")
    with pytest.raises(mjcf.NameClashError, match="already used"):
        model.worldbody.add("body", name="arm")
    with pytest.raises(mjcf.UnknownAttributeError, match="'colour'"):
        body.colour = "red"
    with pytest.raises(mjcf.InvalidReferenceError, match="refers to a joint"):
        model.actuator.add("motor", joint=body)
    with pytest.warns(DeprecationWarning), pytest.raises(mjcf.NameError):  # old name catches
        model.worldbody.add("body", name="arm")
