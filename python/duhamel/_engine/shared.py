"""What models with the same matrices share within a process: the checks of ``M`` and ``K``
and their first modal analysis.

A study often builds its model anew for every run (``make_system(p)`` in
:func:`duhamel.ensemble.solve_many`) with the same mass and stiffness. Checking them
(symmetry, a Cholesky factorisation of ``M``) and computing their modes again each time costs
far more than a short run. Dense matrices are identified by their content (a digest of their
bytes, shapes and dtypes, never by identity), and:

* matrices already checked are not checked again;
* a system's *first* modal analysis of ``n`` modes (nothing computed before on it) is the same
  function of ``(M, K, n)`` and of the damping for every system, so it is taken from an earlier
  system's when there is one — the same numbers, bit for bit. A system that already knows some
  modes grows them as before (:class:`~duhamel._engine.eigen.Modes`), so no result depends on
  what other systems did.

Sparse models (large by nature, where a digest would cost what it saves) are not shared. At
most :data:`KEPT` entries are kept, the oldest dropped first.
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from typing import Any

import numpy as np

from duhamel._engine.validate import issparse

__all__ = ["KEPT", "basis", "checked", "content_key", "remember_basis", "remember_checked"]

#: Entries kept (checked matrix pairs, and first modal bases).
KEPT = 16
#: Largest order whose content is digested (beyond it the checks and eigensolution cost more
#: than anything a digest saves, and the digest itself is not free).
MAX_N = 2000

_CHECKED: OrderedDict[bytes, bool] = OrderedDict()
_BASES: OrderedDict[tuple[Any, ...], tuple[Any, Any, Any, bool]] = OrderedDict()
_LOCK = threading.Lock()


def content_key(*matrices: Any) -> bytes | None:
    """A digest of dense `matrices` (None when one is sparse, too large or not float64)."""
    digest = hashlib.blake2b(digest_size=20)
    for m in matrices:
        if issparse(m) or not isinstance(m, np.ndarray) or m.dtype != np.float64:
            return None
        if m.shape[0] > MAX_N:
            return None
        digest.update(repr(m.shape).encode())
        digest.update(np.ascontiguousarray(m).data)
    return digest.digest()


def _keep(cache: OrderedDict[Any, Any], key: Any, value: Any) -> None:
    with _LOCK:
        cache[key] = value
        cache.move_to_end(key)
        while len(cache) > KEPT:
            cache.popitem(last=False)


def checked(key: bytes | None) -> bool:
    """Whether the matrices of `key` passed the checks before."""
    return key is not None and key in _CHECKED


def remember_checked(key: bytes | None) -> None:
    """Notes that the matrices of `key` passed the checks."""
    if key is not None:
        _keep(_CHECKED, key, True)


def damping_key(system: Any) -> tuple[Any, ...] | None:
    """What the modal damping of `system` depends on besides its modes (None: a sparse
    damping matrix, not shared)."""
    kind = system.damping
    if kind == "none":
        return ("none",)
    if kind == "rayleigh":
        return ("rayleigh", *system.rayleigh)
    if kind == "zeta":
        z = system.zeta
        return ("zeta", float(z)) if isinstance(z, float) else ("zeta", np.asarray(z).tobytes())
    digest = content_key(system.C)  # a damping matrix: shared when dense
    return None if digest is None else ("matrix", digest)


def basis(key: bytes | None, n: int, system: Any) -> tuple[Any, Any, Any, bool] | None:
    """``(lam, phi, basis, semidefinite)`` of an earlier first analysis of `n` modes of the
    same matrices and damping, or None."""
    if key is None:
        return None
    damping = damping_key(system)
    if damping is None:
        return None
    return _BASES.get((key, n, damping))


def remember_basis(
    key: bytes | None, n: int, system: Any, entry: tuple[Any, Any, Any, bool]
) -> None:
    """Keeps the first analysis of `n` modes of `system` (see :func:`basis`)."""
    damping = None if key is None else damping_key(system)
    if damping is not None:
        _keep(_BASES, (key, n, damping), entry)
