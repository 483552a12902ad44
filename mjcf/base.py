"""dm_control's `mjcf.base` module path: `Element`, the class of every element (a
`RootElement` and an attachment frame included), for code that checks

    from mjcf import base
    isinstance(thing, base.Element)
"""

from mjcf.tree.element import Element

__all__ = ["Element"]
