"""The engine's caches of what it derives from a model — the background with the elements'
linear parts (:mod:`duhamel._engine.background`), the static corrections
(:mod:`duhamel._engine.correction`) — held here, by the model object and weakly (an entry
goes with its model), never written into the model itself."""

from __future__ import annotations

import weakref
from typing import Any

__all__ = ["forget", "of", "share"]

_CACHES: weakref.WeakKeyDictionary[Any, dict[str, Any]] = weakref.WeakKeyDictionary()


def of(model: Any) -> dict[str, Any]:
    """The engine's caches of `model` by name (an empty dict the first time)."""
    found = _CACHES.get(model)
    if found is None:
        found = _CACHES[model] = {}
    return found


def share(source: Any, copy: Any, name: str, default: Any = None, *more: tuple[str, Any]) -> None:
    """`copy` takes the cache `name` of `source` (the same object; `default` is first
    given to `source` when it has none, None: nothing to share), and so for each further
    ``(name, default)`` pair of `more` (one look-up of each model's caches for them all)."""
    caches = of(source)
    taken = None
    for key, fallback in ((name, default), *more):
        if key not in caches:
            if fallback is None:
                continue
            caches[key] = fallback
        if taken is None:
            taken = of(copy)
        taken[key] = caches[key]


def forget(model: Any) -> None:
    """Drops every cache of `model` (its matrices changed)."""
    _CACHES.pop(model, None)
