"""A corridor along +x: a floor strip, optional side walls, optional gaps to jump.

    arena = Corridor(length=30, width=3, walls=True, gaps=[(5.0, 0.6), (9.0, 0.8)])
    arena.attach(walker)                 # starts at x = 0, runs toward +x

Without gaps the floor is the arena's plane at z = 0. With gaps it is a row of boxes
whose tops are at z = 0, with holes where `gaps` say (start x, length), above a pit floor
`pit_depth` m down; anything that falls in stays below z = 0.
"""

from __future__ import annotations

from collections.abc import Sequence

import composer
from arenas.floor import Floor


class Corridor(Floor):
    """A `Floor` with walls at y = +-width/2 (if `walls`) from x = -2 to `length`."""

    # _build takes the constructor's arguments (see Entity.__init__): each arena its own.
    def _build(  # type: ignore[override]
        self,
        name: str = "corridor",
        length: float = 30.0,
        width: float = 3.0,
        walls: bool = True,
        wall_height: float = 0.5,
        gaps: Sequence[tuple[float, float]] = (),
        pit_depth: float = 1.0,
    ) -> None:
        """Make the corridor named `name` (sizes in m). Raises composer.EntityError for
        gaps outside the corridor, overlapping or of non-positive length."""
        start = -2.0
        half_x = (length - start) / 2 + 2.0
        center_x = (length + start) / 2
        super()._build(name=name, size=(half_x, max(width, 2.0) * 2))
        root = self.mjcf_model
        self.floor.pos = [center_x, 0, 0]
        self.length, self.width = float(length), float(width)
        if walls:
            root.asset.add("material", name="wall", rgba=[0.45, 0.5, 0.55, 1])
            for side, y in (("left", width / 2), ("right", -width / 2)):
                root.worldbody.add(
                    "geom", name=f"{side}_wall", type="box", material="wall",
                    size=[half_x, 0.05, wall_height / 2], pos=[center_x, y + (0.05 if y > 0
                    else -0.05), wall_height / 2],
                )  # fmt: skip
        self.gaps = _checked_gaps(gaps, start, length)
        if self.gaps:
            self.floor.pos = [center_x, 0, -pit_depth]
            edges = [start - 2.0]
            for gap_start, gap_length in self.gaps:
                edges += [gap_start, gap_start + gap_length]
            edges.append(length + 2.0)
            for index in range(0, len(edges), 2):
                low, high = edges[index], edges[index + 1]
                root.worldbody.add(
                    "geom", name=f"platform_{index // 2}", type="box", material="grid",
                    size=[(high - low) / 2, width / 2, pit_depth / 2],
                    pos=[(high + low) / 2, 0, -pit_depth / 2],
                )  # fmt: skip


def _checked_gaps(
    gaps: Sequence[tuple[float, float]], start: float, length: float
) -> list[tuple[float, float]]:
    ordered = sorted((float(a), float(b)) for a, b in gaps)
    previous_end = start
    for gap_start, gap_length in ordered:
        if gap_length <= 0 or gap_start <= previous_end or gap_start + gap_length >= length:
            raise composer.EntityError(
                f"corridor gap (start {gap_start}, length {gap_length}) must have a positive "
                f"length, lie within x in ({start}, {length}) and not overlap another"
            )
        previous_end = gap_start + gap_length
    return ordered
