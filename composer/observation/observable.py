"""Observables: named features of a simulation, with how and when they are sampled.

    qpos = MJCFFeature('qpos', arm_joints)                   # physics.bind(arm_joints).qpos
    tip = MJCFFeature('xpos', tip_site, update_interval=2)   # sampled every 2nd physics step
    speed = Generic(lambda physics: physics.data.qvel[:1], bounds=(-10, 10))
    image = MJCFCamera(head_camera, height=64, width=64)     # uint8 (64, 64, 3), bounds 0..255
    qpos.configure(buffer_size=3, delay=1, aggregator='mean',
                   corruptor=GaussianNoise(0.01))           # see below
    qpos.enabled = True                                      # observables start disabled

Options, all counted in physics steps from the episode's reset: a sample is taken after
every `update_interval`-th step; it becomes visible `delay` steps later; the observation
holds the `buffer_size` most recent visible samples (leading axis, oldest first, when
`buffer_size > 1`), reduced over that axis by `aggregator` ('mean', 'max', 'min', 'sum' or
a callable `f(buffer, axis=0)`). `corruptor(value, random_state=...)` changes each sample
when it is taken, with the environment's random state passed by keyword as dm_control
passes it (so `variation.noises.Additive(...)` is seeded). Before the episode the feature
is taken to have held its reset value, so early observations repeat it.

Bounds: `bounds=(low, high)` (broadcast to the value's shape) give the observation space's
Box; they are carried through buffers and aggregators ('sum' scales them by the buffer
size). A corruptor makes them unbounded unless it has `bounds(low, high) -> (low, high)`; a
callable aggregator makes them unbounded unless `aggregator_bounds` says otherwise.
Subclasses implement `reader(physics)`, a function of no arguments, resolved once per
compile, that returns the current value in one environment's `mjcf.Physics`; or, to be read
for many environments at once, `batch_reader(physics)`, the same for a `BatchPhysics`,
returning (n, *shape) (`BatchGeneric` wraps a function). Written once: a single environment
reads a batched observable with a batch of one, row 0 (`reader_of`), and a
`VectorEnvironment` reads one without a batched reader once per environment.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

from composer import batched, errors
from composer.batch_of_one import BatchOfOne

AGGREGATORS = ("mean", "max", "min", "sum")

Bounds = tuple[Any, Any]


class Observable:
    """One named feature, sampled into the observation; subclasses say how to read it."""

    def __init__(
        self,
        update_interval: int = 1,
        buffer_size: int = 1,
        delay: int = 0,
        aggregator: str | Callable[..., np.ndarray] | None = None,
        corruptor: Callable[..., np.ndarray] | None = None,  # (value, random_state=...)
        bounds: Bounds | None = None,
        aggregator_bounds: Bounds | None = None,
        enabled: bool = False,
    ) -> None:
        """Set the sampling options (see the module docstring); checked by `validate`."""
        self.update_interval = update_interval
        self.buffer_size = buffer_size
        self.delay = delay
        self.aggregator = aggregator
        self.corruptor = corruptor
        self.bounds = bounds
        self.aggregator_bounds = aggregator_bounds
        self.enabled = enabled

    def configure(self, **options: Any) -> None:
        """Set several options at once; raises ObservableError for an unknown option."""
        for key in options:
            if key not in _OPTIONS:
                raise errors.ObservableError(
                    f"{type(self).__name__} has no option {key!r}; options: {sorted(_OPTIONS)}"
                )
        for key, value in options.items():
            setattr(self, key, value)

    def validate(self, name: str) -> None:
        """Raise ObservableError, naming observable `name`, for an invalid option."""
        for option, least in (("update_interval", 1), ("buffer_size", 1), ("delay", 0)):
            value = getattr(self, option)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < least:
                raise errors.ObservableError(
                    f"observable {name!r}: {option} must be an int >= {least} (in physics steps), "
                    f"got {value!r}"
                )
        aggregator = self.aggregator
        if aggregator is not None and not callable(aggregator) and aggregator not in AGGREGATORS:
            raise errors.ObservableError(
                f"observable {name!r}: aggregator must be one of {AGGREGATORS} or a callable, "
                f"got {aggregator!r}"
            )
        if self.corruptor is not None and not callable(self.corruptor):
            raise errors.ObservableError(
                f"observable {name!r}: corruptor must be callable(value, random_state), "
                f"got {self.corruptor!r}"
            )

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """A function returning the current value in `physics`, resolved once per compile;
        here, row 0 of `batch_reader` with a batch of one. Raises NotImplementedError if
        neither is implemented."""
        read = self.batch_reader(BatchOfOne(physics, strict=False))
        if read is None:
            raise NotImplementedError(
                f"{type(self).__name__} must implement reader(physics) or batch_reader(physics)"
            )
        return lambda: read()[0]

    def batch_reader(self, physics: batched.BatchPhysics) -> Callable[[], np.ndarray] | None:
        """A function returning the current values of the n environments of `physics`,
        shape (n, *shape), resolved once per compile; or None when they cannot be read at
        once (then each environment's is read with `reader`). None here."""
        return None

    def default_bounds(self, value: np.ndarray) -> Bounds:
        """The bounds used when none were given: unbounded (integer types: their range)."""
        return _dtype_range(value.dtype)

    def __call__(self, physics: Any) -> np.ndarray:
        """The current value in `physics` (uncorrupted, unbuffered); for inspection."""
        return np.asarray(reader_of(self, physics)())


_OPTIONS = frozenset(Observable().__dict__)


def reader_of(observable: Observable, physics: Any) -> Callable[[], np.ndarray]:
    """How one environment reads `observable` from its `physics`: its `batch_reader` with a
    batch of one where that is the form it defines (on the class defining `reader` or a
    subclass, as `composer.batched` decides for task methods), else its `reader`."""
    if batched.prefers_batched(type(observable), "reader", "batch_reader"):
        return Observable.reader(observable, physics)
    return observable.reader(physics)


class MJCFFeature(Observable):
    """A field of bound MJCF elements: `physics.bind(elements).<kind>`, e.g. 'qpos',
    'xpos', 'sensordata'; `index` then picks part of it."""

    def __init__(self, kind: str, mjcf_element: Any, index: Any = None, **options: Any) -> None:
        """Read `kind` of `mjcf_element` (one element or a list); options as `Observable`."""
        super().__init__(**options)
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


class Generic(Observable):
    """The value of `function(physics)`, any array-like of a fixed shape."""

    def __init__(self, function: Callable[[Any], Any], **options: Any) -> None:
        """Call `function(physics)` at each sample; options as `Observable`."""
        super().__init__(**options)
        self.function = function

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """A closure over `physics`."""
        function = self.function
        return lambda: function(physics)


class BatchGeneric(Observable):
    """The values of `function(physics)` for the n environments of a `BatchPhysics`, any
    array-like of shape (n, *shape); one environment reads row 0 of a batch of one.

        speed = BatchGeneric(lambda physics: physics.field('qvel')[:, :1], bounds=(-10, 10))
    """

    def __init__(
        self,
        function: Callable[[batched.BatchPhysics], Any],
        batch_function: Callable[[batched.BatchPhysics], Any] | None = None,
        **options: Any,
    ) -> None:
        """Call `function(batch_physics)` at each sample; options as `Observable`.
        Deprecated: the previous release's `BatchGeneric(single_function,
        batch_function=...)` still works, with a DeprecationWarning, and reads
        `batch_function` in every environment."""
        super().__init__(**options)
        if batch_function is not None:
            warnings.warn(
                "BatchGeneric(function, batch_function=...) is deprecated: one environment is "
                "now read with batch_function and a batch of one, so the single-environment "
                "function is not used; pass the batched function alone, "
                "BatchGeneric(batch_function)",
                DeprecationWarning,
                stacklevel=2,
            )
            function = batch_function
        self.batch_function = function

    def batch_reader(self, physics: batched.BatchPhysics) -> Callable[[], np.ndarray]:
        """A closure over the batch physics."""
        function = self.batch_function
        return lambda: np.asarray(function(physics))


class MJCFCamera(Observable):
    """An image from an MJCF camera: (height, width, 3) uint8 RGB bounded to [0, 255], or
    with `depth=True` (height, width) float32 depth in meters, bounded below by 0."""

    def __init__(
        self,
        mjcf_element: Any,
        height: int = 240,
        width: int = 320,
        depth: bool = False,
        **options: Any,
    ) -> None:
        """Render camera `mjcf_element`; options as `Observable`."""
        super().__init__(**options)
        self.mjcf_element = mjcf_element
        self.height = height
        self.width = width
        self.depth = depth

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """Render through the physics' renderer of this size, by camera id."""
        camera_id = physics.bind(self.mjcf_element).ids
        height, width, depth = self.height, self.width, self.depth
        return lambda: physics.render(height, width, camera_id=camera_id, depth=depth)

    def default_bounds(self, value: np.ndarray) -> Bounds:
        """[0, 255] for RGB, [0, inf) for depth."""
        return (0, np.inf) if self.depth else (0, 255)


class GaussianNoise:
    """A corruptor adding zero-mean Gaussian noise of standard deviation `std`."""

    def __init__(self, std: float) -> None:
        """Raises VariationError for a negative `std`."""
        if not std >= 0:
            raise errors.VariationError(f"GaussianNoise std must be >= 0, got {std!r}")
        self.std = std

    def __call__(self, value: np.ndarray, random_state: np.random.RandomState) -> np.ndarray:
        """`value` plus noise drawn from `random_state`."""
        return value + random_state.normal(0.0, self.std, size=np.shape(value))

    def bounds(self, low: np.ndarray, high: np.ndarray) -> Bounds:
        """Noise is unbounded: so are the corrupted values."""
        return np.full_like(low, -np.inf), np.full_like(high, np.inf)


def _dtype_range(dtype: np.dtype) -> Bounds:
    if np.issubdtype(dtype, np.integer):
        info = np.iinfo(dtype)
        return info.min, info.max
    return -np.inf, np.inf
