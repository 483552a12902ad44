"""dm_control's `mjcf.debugging` module path: debug mode, which records where each
element was made (see `mjcf.tree.debugging`)."""

from mjcf.tree.debugging import (
    SourceLocation,
    debug_mode,
    disable_debug_mode,
    enable_debug_mode,
    is_debug_mode,
)

__all__ = [
    "SourceLocation",
    "debug_mode",
    "disable_debug_mode",
    "enable_debug_mode",
    "is_debug_mode",
]
