"""A system's stiffness with a geometric stiffness taken in (P-Delta), checked."""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel._engine.eigen import NEG_EIG_RTOL
from duhamel._engine.validate import as_square_matrix, check_semidefinite, check_symmetric, issparse

__all__ = ["softened"]


def softened(K: Any, Kg: Any, n: int) -> Any:
    """``K - Kg`` (sparse when `K` is), or ValueError naming `Kg` when it is not symmetric
    or makes the stiffness indefinite (the gravity load beyond the buckling load)."""
    Kg = as_square_matrix(Kg, "Kg", n=n, ref="K")
    check_symmetric(Kg, "Kg")
    if issparse(K):
        import scipy.sparse as sp

        out = sp.csr_array(K - sp.csr_array(Kg))
    else:
        out = np.asarray(K) - (Kg.toarray() if issparse(Kg) else np.asarray(Kg))
    try:
        check_semidefinite(out, NEG_EIG_RTOL)
    except ValueError:
        raise ValueError(
            "`Kg`: K - Kg is not positive semidefinite: the gravity loads exceed the buckling "
            "load of the structure (P-Delta instability); check the loads `P` and heights"
        ) from None
    return out
