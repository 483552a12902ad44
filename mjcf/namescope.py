"""dm_control's `mjcf.namescope` module path: `NameScope`, the names of one model's
elements (see `mjcf.tree.namescope`)."""

from mjcf.tree.namescope import PREFIX_SEPARATOR, NameScope

__all__ = ["PREFIX_SEPARATOR", "NameScope"]
