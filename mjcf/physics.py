"""dm_control's `mjcf.physics` module path: `Physics`. Defined in `mjcf.sim.physics`."""

from mjcf.sim.physics import Physics

__all__ = ["Physics"]
