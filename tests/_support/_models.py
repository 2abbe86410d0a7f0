"""Small models several test files build."""

from __future__ import annotations

import numpy as np


def grounded_chain(n: int, k: float) -> np.ndarray:
    """Stiffness of `n` masses in a row, each on a ground spring `k` and linked to the next
    by `k` (dense, symmetric positive definite)."""
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k
        if i + 1 < n:
            K[i : i + 2, i : i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return K
