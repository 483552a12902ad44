"""Exceptions raised by `mjcf`: one base class, `mjcf.Error`, and specific subclasses.

Every message names where the problem is (the element path, the attribute, the file
and line) and what was expected, so one line is enough to find and fix it::

    mjcf.AttributeValueError: <worldbody>/<body name="arm">/<geom name="tip">: 'size'
    takes 1 to 3 numbers, got 4: '1 2 3 4'

Errors that users catch by their builtin meaning also subclass that builtin:
`AttributeError` (so `getattr(element, 'x', None)` and `hasattr` behave), `ValueError`
for bad values, `KeyError` for lookups by name. An unknown namespace in `find` /
`find_all` is a `NamespaceError`: a `NotFoundError` (so a `KeyError`, as before) that is
also the `ValueError` dm_control raises there.
"""

from __future__ import annotations

import builtins


class Error(Exception):
    """Base class of every exception raised by `mjcf`."""


# -- building and editing the tree -------------------------------------------------------


class SchemaError(Error):
    """An element that MJCF does not allow here: unknown tag, wrong parent, or a
    second copy of an element that may appear only once."""


class AttributeError(Error, builtins.AttributeError):
    """An attribute that the element's MJCF schema does not have."""


class AttributeValueError(Error, ValueError):
    """A value of the wrong type, arity or keyword for its attribute, or a missing
    required attribute."""


class NameError(Error, ValueError):
    """A name that is already taken in its namespace, or that is not a valid name."""


class ReferenceError(Error, ValueError):
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


class PhysicsError(Error):
    """The simulation diverged (bad acceleration, NaN or infinite state)."""


class StateError(Error, ValueError):
    """A state or control vector of the wrong size, or a step count below one."""


class BindingError(Error, builtins.AttributeError):
    """An element that cannot be bound to this physics, or a field its kind does not
    have, or a value of the wrong shape."""


class RenderError(Error):
    """No OpenGL backend could be created for rendering."""
