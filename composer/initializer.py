"""dm_control's `composer.initializer` module path: `Initializer` (defined in
`composer.initializers.base`)."""

from composer.initializers.base import Initializer

__all__ = ["Initializer"]
