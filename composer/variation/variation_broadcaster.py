"""VariationBroadcaster: one variation's values shared by several users.

    broadcaster = VariationBroadcaster(Uniform(0.5, 1.5))
    left, right = broadcaster.get_proxy(), broadcaster.get_proxy()
    variator.bind_attributes(left_wheel, size=left)
    variator.bind_attributes(right_wheel, size=right)      # both get the same draw

Promise: proxies each called once per episode all get the same value each episode.
"""

from __future__ import annotations

import collections
import weakref
from typing import Any

from composer.variation import base
from composer.variation.variation_values import evaluate


class VariationBroadcaster:
    """Shares the values of `wrapped_variation` between the proxies it makes.

    The broadcaster draws in rounds: a proxy that has seen every value drawn so far draws a new
    one (with the random state it is called with) and queues it for every proxy; each proxy
    returns its queue's oldest value. With each proxy called once per episode, they all get
    the same value each episode. A proxy no longer referenced stops receiving values.
    """

    def __init__(self, wrapped_variation: Any) -> None:
        """Broadcast the values of `wrapped_variation` (a variation or constant)."""
        self._wrapped_variation = wrapped_variation
        self._queues: weakref.WeakKeyDictionary[_BroadcastProxy, collections.deque[Any]] = (
            weakref.WeakKeyDictionary()
        )

    def get_proxy(self) -> base.Variation:
        """A new variation to use in place of the wrapped one; it starts with the values
        drawn from now on."""
        proxy = _BroadcastProxy(self)
        self._queues[proxy] = collections.deque()
        return proxy

    def _next_value(self, proxy: _BroadcastProxy, random_state: Any) -> Any:
        queue = self._queues[proxy]
        if not queue:
            value = evaluate(self._wrapped_variation, None, None, random_state)
            for pending in self._queues.values():
                pending.append(value)
        return queue.popleft()


class _BroadcastProxy(base.Variation):
    """One user's view of a broadcaster's values."""

    def __init__(self, broadcaster: VariationBroadcaster) -> None:
        self._broadcaster = broadcaster

    def __call__(
        self, initial_value: Any = None, current_value: Any = None, random_state: Any = None
    ) -> Any:
        """This proxy's next value of the broadcast."""
        return self._broadcaster._next_value(self, random_state)
