"""arenas.suite.spline_zoom against scipy.ndimage.zoom, whose values the Control Suite's
quadruped escape terrain is made of: equal to the last bit (a terrain differing in one
float32 height would let every episode drift apart from dm_control's)."""

from __future__ import annotations

import numpy as np
import pytest

from arenas.suite.spline_zoom import spline_zoom

ndimage = pytest.importorskip("scipy.ndimage")


@pytest.mark.parametrize(
    ("shape", "zoom"),
    [((30, 30), 201 / 30.0), ((5, 7), 3.3), ((12, 9), 0.5), ((4, 4), 10.0), ((2, 3), 4.0)],
)
def test_the_zoom_is_scipy_s_to_the_last_bit(shape, zoom):
    random = np.random.RandomState(sum(shape))
    for _ in range(5):
        values = random.uniform(0.15, 1.0, shape)
        np.testing.assert_array_equal(spline_zoom(values, zoom), ndimage.zoom(values, zoom))
