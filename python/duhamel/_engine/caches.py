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


def share(source: Any, copy: Any, name: str, default: Any = None) -> None:
    """`copy` takes the cache `name` of `source` (the same object; `default` is first
    given to `source` when it has none, None: nothing to share)."""
    caches = of(source)
    if name not in caches and default is not None:
        caches[name] = default
    if name in caches:
        of(copy)[name] = caches[name]


def forget(model: Any) -> None:
    """Drops every cache of `model` (its matrices changed)."""
    _CACHES.pop(model, None)
