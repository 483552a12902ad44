"""Observables: named features of a simulation, with how and when they are sampled.

    speed = Generic(lambda physics: physics.data.qvel[:1], bounds=(-10, 10))
    hinge = MujocoFeature('qpos', 'hinge')                   # physics.named.data.qpos['hinge']
    speed.configure(buffer_size=3, delay=1, aggregator='mean', corruptor=GaussianNoise(0.01))
    speed.enabled = True                                     # observables start disabled

Promises (`Observable` states its options, bounds and readers in full): options count physics
steps from the episode's reset; a corruptor draws only from the environment's random state;
an invalid option raises ObservableError, an unknown one ObservableOptionError.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from composer import errors
from composer.batch import protocol
from composer.batch.single import BatchOfOne

Bounds = tuple[Any, Any]
Corruptor = Callable[..., Any]


class Aggregator:
    """A named reduction over a buffer's leading axis: `aggregator(buffer)`."""

    def __init__(self, name: str, reducer: Callable[..., np.ndarray], preserves_bounds: bool):
        """Reduce with `reducer(buffer, axis=0)`; `preserves_bounds` says whether values
        within bounds stay within them."""
        self.name = name
        self.reducer = reducer
        self.preserves_bounds = preserves_bounds

    def __call__(self, buffer: np.ndarray) -> np.ndarray:
        """The reduction of `buffer` over its first axis."""
        return self.reducer(buffer, axis=0)

    def __repr__(self) -> str:
        return f"<aggregator {self.name!r}>"


AGGREGATORS: dict[str, Aggregator] = {
    "min": Aggregator("min", np.min, True),
    "max": Aggregator("max", np.max, True),
    "mean": Aggregator("mean", np.mean, True),
    "median": Aggregator("median", np.median, True),
    "sum": Aggregator("sum", np.sum, False),
}


def _aggregator(value: Any) -> Callable[[np.ndarray], np.ndarray] | None:
    """`value` as an aggregator: None, a callable, or the one `AGGREGATORS` names. Raises
    UnknownAggregatorError (a KeyError) for another name."""
    if value is None or callable(value):
        return value
    try:
        return AGGREGATORS[value]
    except (KeyError, TypeError):
        raise errors.UnknownAggregatorError(
            f"Unrecognized aggregator name: {value!r}. Valid names: {sorted(AGGREGATORS)}, "
            "or a callable f(buffer) reducing the buffer's first axis"
        ) from None


class FieldRows(NamedTuple):
    """What an observable's value is, when it is rows of one MjData field of bound elements:
    `physics.bind(elements).<field>[index]` (`index` None: all of it), then with `angles`
    (cos, sin) of those values concatenated along the last axis, or `function` (a numpy
    ufunc of one argument, e.g. np.log1p) of each, then with `flat` flattened (C order),
    then with `bounds` clipped to (low, high) as `np.minimum(np.maximum(value, low), high)`."""

    field: str
    elements: Any
    index: Any = None
    angles: bool = False
    bounds: tuple[np.ndarray, np.ndarray] | None = None
    flat: bool = False
    function: np.ufunc | None = None


class Observable:
    """One named feature, sampled into the observation; subclasses say how to read it.

    Options, all counted in physics steps from the episode's reset: a sample is taken after
    every `update_interval`-th step; it becomes visible `delay` steps later (None: 0); the
    observation holds the `buffer_size` (None: 1) most recent visible samples (leading axis,
    oldest first, when `buffer_size > 1`), reduced over that axis by `aggregator` (a name of
    `AGGREGATORS` or a callable `f(buffer)`, as dm_control calls it). The corruptor is called
    `corruptor(value, random_state=random_state)`, as dm_control calls it, on each sample when
    it is taken, with the environment's random state. Before the episode the feature is taken
    to have held its reset value (see `composer.ObservationPadding` for zeros instead).

    Bounds: `bounds=(low, high)` (broadcast to the value's shape) give the observation space's
    Box; they are carried through buffers and aggregators ('sum' scales them by the buffer
    size; a callable keeps them if it has `preserves_bounds = True`). A corruptor makes them
    unbounded unless it has `bounds(low, high) -> (low, high)`; a callable aggregator makes them
    unbounded unless `aggregator_bounds` or `preserves_bounds` says otherwise.

    Subclasses implement `reader(physics)` (or dm_control's `_callable(physics)`), a function
    of no arguments, resolved once per compile, that returns the current value in one
    environment's `mjcf.Physics`; or, to be read for many environments at once,
    `batch_reader(physics)`, the same for a `BatchPhysics`, returning (n, *shape)
    (`BatchGeneric` wraps a function). Written once: a single environment reads a batched
    observable with a batch of one, row 0 (`reader_of`), and a `VectorEnvironment` reads one
    without a batched reader once per environment. An observable whose value is rows of one
    bound MjData field, maybe turned into (cos, sin) and clipped, may also say so
    (`field_rows`): a single environment then reads it with the others that do in one gather
    (`composer.observation.fused`), checked against its reader.
    """

    def __init__(
        self,
        update_interval: int = 1,
        buffer_size: int | None = None,
        delay: int | None = None,
        aggregator: str | Callable[[np.ndarray], np.ndarray] | None = None,
        corruptor: Corruptor | None = None,
        *,
        bounds: Bounds | None = None,
        aggregator_bounds: Bounds | None = None,
        enabled: bool = False,
    ) -> None:
        """Set the sampling options (see the class docstring); checked by `validate`.
        Raises UnknownAggregatorError for an aggregator name not in `AGGREGATORS`."""
        self.update_interval = update_interval
        self.buffer_size = buffer_size
        self.delay = delay
        self.aggregator = aggregator
        self.corruptor = corruptor
        self.bounds = bounds
        self.aggregator_bounds = aggregator_bounds
        self.enabled = enabled

    @property
    def aggregator(self) -> Callable[[np.ndarray], np.ndarray] | None:
        """The reduction over the buffer: an `AGGREGATORS` entry, a callable, or None."""
        return self._aggregator

    @aggregator.setter
    def aggregator(self, value: Any) -> None:
        self._aggregator = _aggregator(value)

    @property
    def array_spec(self) -> Any:
        """dm_env's spec of this observable's values, or None when it is learned by
        reading the observable (here)."""
        return None

    def configure(self, **options: Any) -> None:
        """Set several options or attributes at once (`update_interval=2`, or a camera's
        `height=64`). Raises ObservableOptionError (an AttributeError) naming an option
        the observable does not have, and then changes nothing."""
        for key in options:
            if key.startswith("_") or not hasattr(self, key):
                known = sorted(k.lstrip("_") for k in vars(self))
                raise errors.ObservableOptionError(
                    f"Cannot add attribute {key} in configure: {type(self).__name__} has no "
                    f"option {key!r}; options: {known}"
                )
        for key, value in options.items():
            setattr(self, key, value)

    def validate(self, name: str) -> None:
        """Raise ObservableError, naming observable `name`, for an invalid option."""
        for option, least in (("update_interval", 1), ("buffer_size", 1), ("delay", 0)):
            value = getattr(self, option)
            if value is None and option != "update_interval":
                continue
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < least:
                raise errors.ObservableError(
                    f"observable {name!r}: {option} must be an int >= {least} (in physics steps), "
                    f"got {value!r}"
                )
        if self.corruptor is not None and not callable(self.corruptor):
            raise errors.ObservableError(
                f"observable {name!r}: corruptor must be callable(value, random_state=...), "
                f"got {self.corruptor!r}"
            )

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """A function returning the current value in `physics`, resolved once per compile:
        dm_control's `_callable(physics)` where a subclass defines it, else row 0 of
        `batch_reader` with a batch of one. Raises NotImplementedError if none is."""
        if type(self)._callable is not Observable._callable:
            return self._callable(physics)
        read = self.batch_reader(BatchOfOne(physics, strict=False))
        if read is None:
            raise NotImplementedError(
                f"{type(self).__name__} must implement reader(physics) or batch_reader(physics) "
                "(or dm_control's _callable(physics))"
            )
        return lambda: read()[0]

    def _callable(self, physics: Any) -> Callable[[], Any]:
        """dm_control's name for `reader`: the uncorrupted reading function."""
        return reader_of(self, physics)

    def batch_reader(self, physics: protocol.BatchPhysics) -> Callable[[], np.ndarray] | None:
        """A function returning the current values of the n environments of `physics`,
        shape (n, *shape), resolved once per compile; or None when they cannot be read at
        once (then each environment's is read with `reader`). None here."""
        return None

    def field_rows(self) -> FieldRows | tuple[FieldRows, ...] | None:
        """What the value is as rows of one bound MjData field (see `FieldRows`), or of
        several (a tuple: their values concatenated along the last axis), for a single
        environment to read it together with other such observables; None (here): only
        the reader says. The class defining this must be the one defining the reader (or
        a subclass), and the value it describes is checked against the reader's at each
        compile."""
        return None

    def default_bounds(self, value: np.ndarray) -> Bounds:
        """The bounds used when none were given: unbounded (integer types: their range)."""
        return _dtype_range(value.dtype)

    def observation_callable(
        self, physics: Any, random_state: np.random.RandomState | None = None
    ) -> Callable[[], Any]:
        """A function of no arguments returning the current value in `physics`, corrupted
        by the corruptor (called with `random_state=random_state`) if there is one."""
        read = reader_of(self, physics)
        corruptor = self.corruptor
        if corruptor is None:
            return read
        return lambda: corruptor(read(), random_state=random_state)

    def __call__(self, physics: Any, random_state: np.random.RandomState | None = None) -> Any:
        """One reading in `physics` (corrupted with `random_state` if there is a
        corruptor), unbuffered; for inspection."""
        return self.observation_callable(physics, random_state)()


def reader_of(observable: Observable, physics: Any) -> Callable[[], np.ndarray]:
    """How one environment reads `observable` from its `physics`: its `batch_reader` with a
    batch of one where that is the form it defines (on the class defining `reader` or a
    subclass, as `composer.batch` decides for task methods), else its `reader`."""
    if protocol.prefers_batched(type(observable), "reader", "batch_reader"):
        return Observable.reader(observable, physics)
    return observable.reader(physics)


def row_reader_of(observable: Observable, physics: Any) -> Callable[[], Any]:
    """How one environment reads `observable` as a row of one: where `reader_of` reads
    row 0 of its `batch_reader` with a batch of one, that batch reader (values of shape
    (1, *shape)); else `reader_of`'s reader (one value, which a row broadcasts)."""
    batched = protocol.prefers_batched(type(observable), "reader", "batch_reader")
    if batched and type(observable)._callable is Observable._callable:
        read = observable.batch_reader(BatchOfOne(physics, strict=False))
        if read is not None:
            return read
    return reader_of(observable, physics)


class Generic(Observable):
    """The value of `raw_observation_callable(physics)`, any array-like of a fixed shape."""

    def __init__(
        self,
        raw_observation_callable: Callable[[Any], Any],
        update_interval: int = 1,
        buffer_size: int | None = None,
        delay: int | None = None,
        aggregator: str | Callable[[np.ndarray], np.ndarray] | None = None,
        corruptor: Corruptor | None = None,
        **options: Any,
    ) -> None:
        """Call `raw_observation_callable(physics)` at each sample; options as `Observable`."""
        super().__init__(update_interval, buffer_size, delay, aggregator, corruptor, **options)
        self.function = raw_observation_callable

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """A closure over `physics`."""
        function = self.function
        return lambda: function(physics)


class MujocoFeature(Observable):
    """A field of MuJoCo objects by name: `physics.named.data.<kind>[feature_name]`;
    `feature_name` is a name, a list of names, or a callable returning either."""

    def __init__(
        self,
        kind: str,
        feature_name: str | list[str] | Callable[[], Any],
        update_interval: int = 1,
        buffer_size: int | None = None,
        delay: int | None = None,
        aggregator: str | Callable[[np.ndarray], np.ndarray] | None = None,
        corruptor: Corruptor | None = None,
        **options: Any,
    ) -> None:
        """Read field `kind` (an MjData field name) of `feature_name`; options as
        `Observable`."""
        super().__init__(update_interval, buffer_size, delay, aggregator, corruptor, **options)
        self.kind = kind
        self.feature_name = feature_name

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """Index the named field each call (a callable name is called each time)."""
        indexer = getattr(physics.named.data, self.kind)
        name = self.feature_name
        if callable(name):
            return lambda: indexer[name()]
        return lambda: indexer[name]


class MujocoCamera(Observable):
    """An image from a camera by name: (height, width, 3) uint8 RGB, or with `depth=True`
    (height, width, 1) float32 depth in meters."""

    def __init__(
        self,
        camera_name: str | int,
        height: int = 240,
        width: int = 320,
        update_interval: int = 1,
        buffer_size: int | None = None,
        delay: int | None = None,
        aggregator: str | Callable[[np.ndarray], np.ndarray] | None = None,
        corruptor: Corruptor | None = None,
        depth: bool = False,
        **options: Any,
    ) -> None:
        """Render camera `camera_name` (a name or id); options as `Observable`."""
        super().__init__(update_interval, buffer_size, delay, aggregator, corruptor, **options)
        self.camera_name = camera_name
        self.height = height
        self.width = width
        self.depth = depth

    @property
    def array_spec(self) -> Any:
        """dm_env's BoundedArray of the image (needs dm-env: the `[dm]` extra)."""
        kind = "depth" if self.depth else "rgb"
        return image_spec(kind, self.height, self.width)

    def reader(self, physics: Any) -> Callable[[], np.ndarray]:
        """Render through the physics' renderer of this size."""
        height, width, depth, camera = self.height, self.width, self.depth, self.camera_name
        return lambda: np.atleast_3d(physics.render(height, width, camera_id=camera, depth=depth))

    def default_bounds(self, value: np.ndarray) -> Bounds:
        """[0, 255] for RGB, [0, inf) for depth."""
        return (0, np.inf) if self.depth else (0, 255)


class BatchGeneric(Observable):
    """The values of `function(physics)` for the n environments of a `BatchPhysics`, any
    array-like of shape (n, *shape); one environment reads row 0 of a batch of one.

        speed = BatchGeneric(lambda physics: physics.field('qvel')[:, :1], bounds=(-10, 10))
    """

    def __init__(
        self,
        function: Callable[[protocol.BatchPhysics], Any],
        batch_function: Callable[[protocol.BatchPhysics], Any] | None = None,
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

    def batch_reader(self, physics: protocol.BatchPhysics) -> Callable[[], np.ndarray]:
        """A closure over the batch physics."""
        function = self.batch_function
        return lambda: np.asarray(function(physics))


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


_IMAGE_KINDS: dict[str, tuple[int, type]] = {
    "rgb": (3, np.uint8),
    "depth": (1, np.float32),
    "segmentation": (2, np.int32),
}
_IMAGE_BOUNDS: dict[str, tuple[float, float]] = {
    "rgb": (0, 255),
    "depth": (0.0, np.inf),
    "segmentation": (-1, int(np.iinfo(np.int32).max)),
}


def image_spec(kind: str, height: int, width: int) -> Any:
    """dm_env's BoundedArray of a camera image of `kind` ('rgb', 'depth' or
    'segmentation'), as dm_control's cameras declare it. Raises composer.Error when dm-env
    is not installed."""
    try:
        from dm_env import specs
    except ImportError:
        raise errors.ObservableError(
            "array_spec is a dm_env spec, which needs dm-env: pip install -e '.[dm]' from a "
            "checkout (or: pip install dm-env)"
        ) from None
    channels, dtype = _IMAGE_KINDS[kind]
    low, high = _IMAGE_BOUNDS[kind]
    return specs.BoundedArray(
        shape=(height, width, channels), dtype=dtype, minimum=low, maximum=high
    )


def _dtype_range(dtype: np.dtype) -> Bounds:
    if np.issubdtype(dtype, np.integer):
        info = np.iinfo(dtype)
        return info.min, info.max
    return -np.inf, np.inf
