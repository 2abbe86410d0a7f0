"""The engine's caches of what it derives from a model — the background with the elements'
linear parts (:mod:`duhamel._engine.background`), the static corrections
(:mod:`duhamel._engine.correction`) — held here, by the model object and weakly (an entry
goes with its model), never written into the model itself."""

from __future__ import annotations

import weakref
from typing import Any

__all__ = ["forget", "of", "share"]


class _Ref(weakref.ref):  # type: ignore[type-arg]
    """A weak reference to a model that knows its model's key in :data:`_CACHES`."""

    __slots__ = ("key",)
    key: int


def _drop(ref: _Ref) -> None:
    """The model of `ref` is gone: its caches go (unless its key holds a newer model's)."""
    entry = _CACHES.get(ref.key)
    if entry is not None and entry[0] is ref:
        del _CACHES[ref.key]


#: Per model, by ``id``: a weak reference to it (the entry is its model's while the reference
#: returns it; dropped when the model goes) and its caches. A dict by ``id`` rather than a
#: ``WeakKeyDictionary``: a look-up makes no new weak reference (it runs several times a run).
_CACHES: dict[int, tuple[_Ref, dict[str, Any]]] = {}


def of(model: Any) -> dict[str, Any]:
    """The engine's caches of `model` by name (an empty dict the first time)."""
    key = id(model)
    entry = _CACHES.get(key)
    if entry is not None and entry[0]() is model:
        return entry[1]
    ref = _Ref(model, _drop)
    ref.key = key
    found: dict[str, Any] = {}
    _CACHES[key] = (ref, found)
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
    entry = _CACHES.get(id(model))
    if entry is not None and entry[0]() is model:
        del _CACHES[id(model)]
