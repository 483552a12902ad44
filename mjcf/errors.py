"""Exceptions raised by `mjcf`: one base class, `mjcf.Error`, and specific subclasses.

Every message names where the problem is (element path, attribute, file and line) and what
was expected, so one line is enough to find and fix it:

    mjcf.AttributeValueError: <worldbody>/<body name="arm">/<geom name="tip">: 'size'
    takes 1 to 3 numbers, got 4: '1 2 3 4'

Errors caught by their builtin meaning also subclass that builtin (`AttributeError`,
`ValueError`, `KeyError`); none is named after a builtin, so `from mjcf import *` is safe.
"""

from __future__ import annotations

import difflib
import warnings
from collections.abc import Iterable


class Error(Exception):
    """Base class of every exception raised by `mjcf`."""


# -- building and editing the tree -------------------------------------------------------


class SchemaError(Error, ValueError, AttributeError):
    """An element that MJCF does not allow here: unknown tag, wrong parent, or a
    second copy of an element that may appear only once. Both a `ValueError` and an
    `AttributeError`, the two dm_control raises for these."""


class UnknownAttributeError(Error, AttributeError):
    """An attribute that the element's MJCF schema does not have; an `AttributeError`, so
    that `getattr(element, 'x', None)` and `hasattr` behave."""


class AttributeValueError(Error, ValueError):
    """A value of the wrong type, arity or keyword for its attribute, or a missing
    required attribute."""


class NameClashError(Error, ValueError):
    """A name that is already taken in its namespace (or, for a model, among the models
    attached to the same model), or that clashes with the separator '/' of scoped
    names."""


class InvalidReferenceError(Error, ValueError):
    """A reference attribute naming an element that does not exist, or an element of
    another model."""


class NotFoundError(Error, KeyError):
    """A lookup by name of something that does not exist: an element of an element list
    (`body.geom['x']`), a row of a named indexer, a keyframe."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class NamespaceError(NotFoundError, ValueError):
    """`find` / `find_all` of a namespace that does not exist. A `ValueError`, as in
    dm_control, and a `NotFoundError` (`KeyError`) for code that caught that."""


class ParseError(Error, ValueError):
    """Malformed or unsafe XML, an `<include>` cycle or a missing included file; the
    message names the file and line."""


class UnpackLimitError(ParseError):
    """A zip entry that unpacks to more than the limits on untrusted archives allow (a
    decompression bomb), or a limit that is not a size or ratio: see `mjcf.archives`."""


class MissingFileError(ParseError, FileNotFoundError):
    """An included file found neither in the `assets` given nor on disk: a ParseError,
    and a `FileNotFoundError` (an `OSError`, which dm_control raises)."""


# -- composition and assets -------------------------------------------------------------


class AttachmentError(Error, ValueError):
    """An attachment that would make the tree invalid (attaching a model to itself or
    to its descendant, attaching one model twice, conflicting compiler settings)."""


class AssetError(Error, ValueError):
    """A missing asset file, or two assets with one file name and different contents."""


# -- simulation ----------------------------------------------------------------------------


class CompileError(Error):
    """MuJoCo rejected the model; in debug mode the message names the element and the
    Python line that created it."""


class BudgetError(CompileError, ValueError):
    """A model that asks MuJoCo for more elements or memory than `mjcf.budget` allows (a
    tiny file that would compile for minutes or allocate gigabytes), or a budget that is
    not a number."""


class PhysicsError(Error):
    """The simulation diverged (bad acceleration, NaN or infinite state)."""


class StateError(Error, ValueError):
    """A state or control vector of the wrong size, or a step count below one."""


class BindingError(Error, AttributeError, ValueError):
    """An element that cannot be bound to this physics, or a field its kind does not
    have (a mocap field of a body that is not mocap), or a value of the wrong shape.
    Both an `AttributeError` and a `ValueError`, the two dm_control raises for these."""


class RenderError(Error):
    """No OpenGL backend could be created for rendering."""


# -- the previous release's names ---------------------------------------------------------

# The previous release called three exceptions after the builtin they subclass, which
# `from mjcf import *` then shadowed; the old names still work, with a DeprecationWarning,
# until the next release, and are not in `__all__` (mjcf.AttributeError is now
# mjcf.UnknownAttributeError, an AttributeError; NameError NameClashError and ReferenceError
# InvalidReferenceError, both ValueErrors).
DEPRECATED_NAMES: dict[str, type[Error]] = {
    "AttributeError": UnknownAttributeError,
    "NameError": NameClashError,
    "ReferenceError": InvalidReferenceError,
}


def deprecated_name(module: str, name: str) -> type[Error]:
    """The exception class an old name of module `module` stands for (see
    `DEPRECATED_NAMES`), with a DeprecationWarning; raises AttributeError, as a module
    does, for any other name."""
    renamed = DEPRECATED_NAMES.get(name)
    if renamed is None:
        raise AttributeError(f"module {module!r} has no attribute {name!r}")
    warnings.warn(
        f"{module}.{name} is now {module}.{renamed.__name__} (the old name shadowed Python's "
        f"builtin {name}); it will be removed in the next release",
        DeprecationWarning,
        stacklevel=3,
    )
    return renamed


def __getattr__(name: str) -> type[Error]:
    return deprecated_name(__name__, name)


def did_you_mean(word: str, choices: Iterable[str], n: int = 3) -> str:
    """ " (did you mean 'a', 'b'?)" for up to `n` of `choices` close to `word`, or "": every
    message's suggestion of the closest names."""
    close = difflib.get_close_matches(word, list(choices), n=n, cutoff=0.6)
    return f" (did you mean {', '.join(map(repr, close))}?)" if close else ""
