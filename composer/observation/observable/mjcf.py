"""Observables of MJCF elements: a bound field (`MJCFFeature`) or a camera (`MJCFCamera`).

    qpos = MJCFFeature('qpos', arm_joints)                   # physics.bind(arm_joints).qpos
    height = MJCFFeature('xpos', torso)[2]                   # an index: a new observable
    tip = MJCFFeature('xpos', tip_site, update_interval=2)   # sampled every 2nd physics step
    image = MJCFCamera(head_camera, height=64, width=64)     # uint8 (64, 64, 3), bounds 0..255
    image.configure(height=32, width=32)

Options are `Observable`'s (`composer.observation.observable.base`); a camera draws through
its physics' renderer of its size, made once per compile.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

import mjcf
from composer import errors
from composer.observation.observable.base import (
    Bounds,
    Corruptor,
    FieldRows,
    Observable,
    image_spec,
)

_BOTH_SEGMENTATION_AND_DEPTH_ENABLED = (
    "`segmentation` and `depth` cannot both be `True`: a camera observable renders one image"
)


def _check_element(element: Any, what: str) -> None:
    if not isinstance(element, mjcf.Element):
        raise errors.ObservableError(f"{what}: expected an `mjcf.Element`, got {element!r}")


def _check_elements(elements: Any) -> None:
    """Raise ObservableError unless `elements` is an element or an iterable of them."""
    if isinstance(elements, mjcf.Element):
        return
    if isinstance(elements, str) or not isinstance(elements, Iterable):
        raise errors.ObservableError(
            f"MJCFFeature: expected an `mjcf.Element` or a list of them, got {elements!r}"
        )
    for element in elements:
        _check_element(element, "MJCFFeature")


class MJCFFeature(Observable):
    """A field of bound MJCF elements: `physics.bind(elements).<kind>`, e.g. 'qpos',
    'xpos', 'sensordata'; `index` (or `feature[index]`) then picks part of it."""

    def __init__(
        self,
        kind: str,
        mjcf_element: Any,
        update_interval: int = 1,
        buffer_size: int | None = None,
        delay: int | None = None,
        aggregator: str | Callable[[np.ndarray], np.ndarray] | None = None,
        corruptor: Corruptor | None = None,
        index: Any = None,
        **options: Any,
    ) -> None:
        """Read `kind` of `mjcf_element` (one element or a list); options as `Observable`.
        Raises ObservableError (a ValueError) for anything but elements."""
        _check_elements(mjcf_element)
        super().__init__(update_interval, buffer_size, delay, aggregator, corruptor, **options)
        self.kind = kind
        self.mjcf_element = mjcf_element
        self.index = index

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """Bind the elements once; each call reads the field through the binding."""
        elements = self.mjcf_element
        binding = physics.bind(list(elements) if isinstance(elements, tuple) else elements)
        kind, index = self.kind, self.index
        getattr(binding, kind)  # raises mjcf.BindingError now for an unknown field
        if index is None:
            return lambda: getattr(binding, kind)
        return lambda: getattr(binding, kind)[index]

    def field_rows(self) -> FieldRows:
        """The field `kind` of the elements, part `index` of it."""
        elements = self.mjcf_element
        return FieldRows(self.kind, list(elements) if isinstance(elements, tuple) else elements,
                         self.index)  # fmt: skip

    def __getitem__(self, key: Any) -> MJCFFeature:
        """A new observable of the same field and options reading `field[key]`. Raises
        ObservableError for an observable that has an index already."""
        if self.index is not None:
            raise errors.ObservableError(
                f"MJCFFeature({self.kind!r}) already has index {self.index!r}: index the "
                "unindexed feature once"
            )
        return MJCFFeature(
            self.kind, self.mjcf_element, self.update_interval, self.buffer_size, self.delay,
            self.aggregator, self.corruptor, key, bounds=self.bounds,
            aggregator_bounds=self.aggregator_bounds, enabled=self.enabled,
        )  # fmt: skip


class MJCFCamera(Observable):
    """An image from an MJCF camera: (height, width, 3) uint8 RGB bounded to [0, 255]; with
    `depth=True` (height, width, 1) float32 depth in meters, bounded below by 0; with
    `segmentation=True` (height, width, 2) int32 (object id, object type), -1 for none.
    It renders through the physics' renderer of its size, made once per compile: frames up
    to 128 pixels a side are drawn without shadows and multisampling unless the model's
    `<visual>` sets them (`mjcf.sim.rendering`)."""

    def __init__(
        self,
        mjcf_element: Any,
        height: int = 240,
        width: int = 320,
        update_interval: int = 1,
        buffer_size: int | None = None,
        delay: int | None = None,
        aggregator: str | Callable[[np.ndarray], np.ndarray] | None = None,
        corruptor: Corruptor | None = None,
        depth: bool = False,
        segmentation: bool = False,
        scene_option: Any = None,
        render_flag_overrides: Any = None,
        **options: Any,
    ) -> None:
        """Render camera `mjcf_element` (a `<camera>` element), with `scene_option` (a
        `mujoco.MjvOption`) if given; options as `Observable`. Raises ObservableError (a
        ValueError) for another element, for both `depth` and `segmentation`, and for
        `render_flag_overrides`, which this renderer does not take."""
        _check_element(mjcf_element, "MJCFCamera")
        if mjcf_element.tag != "camera":
            raise errors.ObservableError(f"expected a <camera> element: got {mjcf_element}")
        if depth and segmentation:
            raise errors.ObservableError(_BOTH_SEGMENTATION_AND_DEPTH_ENABLED)
        if render_flag_overrides is not None:
            raise errors.ObservableError(
                "MJCFCamera: render_flag_overrides is not supported; set the flags in "
                "scene_option (a mujoco.MjvOption) or in the model's <visual>"
            )
        super().__init__(update_interval, buffer_size, delay, aggregator, corruptor, **options)
        self.mjcf_element = mjcf_element
        self.height = height
        self.width = width
        self.depth = depth
        self.segmentation = segmentation
        self.scene_option = scene_option

    @property
    def array_spec(self) -> Any:
        """dm_env's BoundedArray of the image (needs dm-env: the `[dm]` extra)."""
        kind = "segmentation" if self.segmentation else "depth" if self.depth else "rgb"
        return image_spec(kind, self.height, self.width)

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """Render through the physics' renderer of this size, by camera id."""
        camera_id = physics.bind(self.mjcf_element).element_id
        height, width, depth = self.height, self.width, self.depth
        segmentation, scene_option = self.segmentation, self.scene_option

        def read() -> np.ndarray:
            return np.atleast_3d(
                physics.render(
                    height,
                    width,
                    camera_id=camera_id,
                    depth=depth,
                    segmentation=segmentation,
                    scene_option=scene_option,
                )
            )

        return read

    def default_bounds(self, value: np.ndarray) -> Bounds:
        """[0, 255] for RGB, [0, inf) for depth, [-1, int32 max] for segmentation."""
        if self.segmentation:
            return -1, np.iinfo(np.int32).max
        return (0, np.inf) if self.depth else (0, 255)
