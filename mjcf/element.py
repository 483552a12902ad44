"""dm_control's `mjcf.element` module path: `RootElement`, `Element` and `_ElementImpl`
(dm_control's name for the class of every element, which code uses as a type:
`MjcfElement = mjcf.element._ElementImpl`). Defined in `mjcf.tree`."""

from mjcf.tree.element import Element
from mjcf.tree.root import RootElement

_ElementImpl = Element

__all__ = ["Element", "RootElement"]
