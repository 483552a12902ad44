"""Props: simple rigid objects (box, sphere, capsule, cylinder, mesh) to place in a scene.

    box = Box(half_sizes=(0.05, 0.05, 0.05), mass=0.2, rgba=(0.8, 0.2, 0.2, 1))
    arena.attach(box)                                   # free=True: it carries a free joint
    box.set_pose(physics, position=[0.5, 0, 0.05])
    fixed = Cylinder(radius=0.1, half_length=0.3, free=False)   # welded where attached

Every prop is one body `body` with one geom `geom`; a free prop's (the default) free joint
`free` lets `set_pose`, `set_velocity` and `PropPlacer` move it after a plain `attach`.
Observables (disabled): `position`, `orientation`, for a free prop `velocity` (6 numbers).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import composer
import mjcf
from entities import features

Color = Sequence[float]


class PropError(composer.EntityError):
    """A prop was given sizes, a mass or a mesh file it cannot use."""


class Prop(composer.Entity):
    """One body with one geom; subclasses choose the geom (see the module docstring)."""

    def _build(
        self,
        name: str,
        geom: dict[str, Any],
        mass: float | None = None,
        rgba: Color = (0.7, 0.7, 0.7, 1.0),
        free: bool = True,
    ) -> None:
        """Make the prop model named `name` whose geom has the attributes `geom`; `mass`
        in kg (None: from density 1000). Raises PropError for a non-positive mass."""
        if mass is not None and not mass > 0:
            raise PropError(f"prop {name!r}: mass must be positive, got {mass!r}")
        root = self._mjcf_root = mjcf.RootElement(model=name)
        self.body = root.worldbody.add("body", name="body")
        self.free_joint = self.body.add("freejoint", name="free") if free else None
        self.geom = self.body.add("geom", name="geom", rgba=list(rgba), **geom)
        if mass is not None:
            self.geom.mass = mass

    def _build_observables(self) -> composer.Observables:
        observables = composer.Observables(self)
        observables.add_observable("position", features.positions(self.body), enabled=False)
        observables.add_observable(
            "orientation", features.Clipped("xquat", self.body, -1.0, 1.0),
            enabled=False,
        )  # fmt: skip
        if self.free_joint is not None:
            observables.add_observable(
                "velocity", features.velocities(self.free_joint), enabled=False
            )
        return observables


def _positive(name: str, **values: Any) -> None:
    for key, value in values.items():
        array = [value] if isinstance(value, int | float) else list(value)
        if not all(isinstance(v, int | float) and v > 0 for v in array):
            raise PropError(f"prop {name!r}: {key} must be positive, got {value!r}")


class Box(Prop):
    """A box of half sizes (x, y, z) in m."""

    def _build(  # type: ignore[override]
        self,
        name: str = "box",
        half_sizes: Sequence[float] = (0.05, 0.05, 0.05),
        mass: float | None = None,
        rgba: Color = (0.8, 0.3, 0.2, 1.0),
        free: bool = True,
    ) -> None:
        """Raises PropError for sizes that are not three positive numbers."""
        _positive(name, half_sizes=half_sizes)
        if len(half_sizes) != 3:
            raise PropError(f"prop {name!r}: half_sizes takes 3 numbers, got {half_sizes!r}")
        super()._build(name, {"type": "box", "size": list(half_sizes)}, mass, rgba, free)


class Sphere(Prop):
    """A sphere of `radius` m."""

    def _build(  # type: ignore[override]
        self,
        name: str = "sphere",
        radius: float = 0.05,
        mass: float | None = None,
        rgba: Color = (0.2, 0.6, 0.8, 1.0),
        free: bool = True,
    ) -> None:
        """Raises PropError for a non-positive radius."""
        _positive(name, radius=radius)
        super()._build(name, {"type": "sphere", "size": [radius]}, mass, rgba, free)


class Capsule(Prop):
    """A capsule along its local z: `radius` and cylinder `half_length` in m."""

    def _build(  # type: ignore[override]
        self,
        name: str = "capsule",
        radius: float = 0.03,
        half_length: float = 0.08,
        mass: float | None = None,
        rgba: Color = (0.3, 0.7, 0.3, 1.0),
        free: bool = True,
    ) -> None:
        """Raises PropError for a non-positive radius or half length."""
        _positive(name, radius=radius, half_length=half_length)
        geom = {"type": "capsule", "size": [radius, half_length]}
        super()._build(name, geom, mass, rgba, free)


class Cylinder(Prop):
    """A cylinder along its local z: `radius` and `half_length` in m."""

    def _build(  # type: ignore[override]
        self,
        name: str = "cylinder",
        radius: float = 0.04,
        half_length: float = 0.06,
        mass: float | None = None,
        rgba: Color = (0.8, 0.7, 0.2, 1.0),
        free: bool = True,
    ) -> None:
        """Raises PropError for a non-positive radius or half length."""
        _positive(name, radius=radius, half_length=half_length)
        geom = {"type": "cylinder", "size": [radius, half_length]}
        super()._build(name, geom, mass, rgba, free)


class MeshProp(Prop):
    """A prop shaped by a mesh file (.stl, .obj, .msh), scaled by `scale` (one factor or
    three); collisions use the mesh's convex hull, as MuJoCo does."""

    def _build(  # type: ignore[override]
        self,
        path: str | os.PathLike[str],
        name: str | None = None,
        scale: float | Sequence[float] = 1.0,
        mass: float | None = None,
        rgba: Color = (0.7, 0.7, 0.7, 1.0),
        free: bool = True,
    ) -> None:
        """Read the mesh at `path` (the prop is named after the file unless `name`).
        Raises PropError when the file cannot be read or `scale` is not positive."""
        file = Path(path)
        name = name or file.stem
        _positive(name, scale=scale)
        try:
            contents = file.read_bytes()
        except OSError as e:
            raise PropError(f"prop {name!r}: cannot read mesh file {str(file)!r}: {e}") from e
        factors = [scale] * 3 if isinstance(scale, int | float) else list(scale)
        asset = mjcf.Asset(contents, file.suffix, prefix=file.stem)
        super()._build(name, {"type": "mesh"}, mass, rgba, free)
        self.mesh = self.mjcf_model.asset.add("mesh", name="mesh", file=asset, scale=factors)
        self.geom.mesh = self.mesh
