"""The low walls around the square of the suite's point-mass and reacher domains.

    walls = add_walls(root.worldbody)    # wall_x, wall_y, wall_neg_x, wall_neg_y

Four planes 4 cm high on the edges of a 0.6 m square, facing in, of the suite's
`decoration` material. Both domains' files draw them in the world; here they travel with
the robot, as its material does (`entities.suite.materials`), so that the composed model
keeps the file's order of geoms and materials.
"""

from __future__ import annotations

import mjcf

_HALF_SIDE, _HALF_HEIGHT, _GRID_SPACING = 0.3, 0.02, 0.02


def add_walls(body: mjcf.Element) -> tuple[mjcf.Element, ...]:
    """Add the four walls to `body` (a model's worldbody) in the suite's order: the ones
    at -x, -y, +x, +y. Returns them."""
    walls = []
    for prefix, side in (("wall", -1), ("wall_neg", 1)):
        for axis, axis_name in enumerate("xy"):
            pos, zaxis = [0.0, 0.0, _HALF_HEIGHT], [0, 0, 0]
            pos[axis], zaxis[axis] = side * _HALF_SIDE, -side  # facing the square's centre
            size = [_HALF_SIDE, _HALF_SIDE, _GRID_SPACING]
            size[axis] = _HALF_HEIGHT
            walls.append(
                body.add(
                    "geom", name=f"{prefix}_{axis_name}", type="plane", pos=pos, zaxis=zaxis,
                    size=size, material="decoration",
                )
            )  # fmt: skip
    return tuple(walls)
