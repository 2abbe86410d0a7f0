"""Small named input-check helpers.

Every helper takes the user-facing parameter name and quotes it in backticks in its error
messages, e.g. ``"`M` must be a square matrix, got shape (3, 4)"``. Bad values raise
:class:`ValueError`, values of the wrong kind (a string or a bool where a number is expected,
complex or object arrays, ...) raise :class:`TypeError`.
"""

from __future__ import annotations

import math
import numbers
import sys
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "as_float_array",
    "as_square_matrix",
    "check_mass",
    "check_nonneg_diagonal",
    "check_positive_definite",
    "check_semidefinite",
    "check_symmetric",
    "dof_index",
    "dof_list",
    "finite_float",
    "flag",
    "int_in_range",
    "issparse",
    "mode_count",
    "nonneg_float",
    "positive_float",
    "positive_int",
    "symmetric_lu",
    "warn_heavy_damping",
]

#: Sparse positive-definiteness checks densify up to this size (dense Cholesky).
DENSE_CHOLESKY_MAX_N = 2000
#: A Cholesky/LDL pivot this small relative to its diagonal entry means "numerically singular".
#: The ratio is invariant under diagonal scaling, so badly scaled units do not trip it.
SINGULAR_PIVOT_RTOL = 1e-12


def _kind_name(dtype: np.dtype) -> str:
    names = {"b": "bool", "c": "complex", "O": "object", "U": "string", "S": "bytes"}
    return names.get(dtype.kind, str(dtype))


def _fmt_shape(shape: tuple[int | None, ...]) -> str:
    parts = ["?" if s is None else str(s) for s in shape]
    return "(" + ", ".join(parts) + ("," if len(parts) == 1 else "") + ")"


def _fmt_index(index: tuple[int, ...]) -> str:
    return str(index[0]) if len(index) == 1 else "(" + ", ".join(map(str, index)) + ")"


def _check_real_dtype(dtype: np.dtype, name: str) -> None:
    if dtype.kind not in "fiu":
        raise TypeError(f"`{name}` must contain real numbers, got dtype {_kind_name(dtype)}")


def as_float_array(
    value: Any,
    name: str,
    ndim: int | None = None,
    shape: tuple[int | None, ...] | None = None,
    *,
    finite: bool = True,
) -> NDArray[np.float64]:
    """Convert `value` to a C-contiguous float64 array, checking dtype, shape and finiteness.

    Integer and lower-precision float inputs are converted; bool, complex, object and string
    data raise TypeError. `shape` may contain ``None`` as a wildcard. The input is copied only
    when needed (non-float64 or non-contiguous).
    """
    if issparse(value):
        raise TypeError(f"`{name}` must be a dense array, got a scipy.sparse matrix")
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"`{name}` could not be converted to an array: {exc}") from None
    _check_real_dtype(arr.dtype, name)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(
            f"`{name}` must be a {ndim}-D array, got a {arr.ndim}-D array of shape {arr.shape}"
        )
    if shape is not None:
        ok = len(shape) == arr.ndim and all(
            s is None or s == a for s, a in zip(shape, arr.shape, strict=False)
        )
        if not ok:
            raise ValueError(f"`{name}` must have shape {_fmt_shape(shape)}, got {arr.shape}")
    arr = np.asarray(arr, dtype=np.float64, order="C")  # keeps 0-d (ascontiguousarray doesn't)
    if finite:
        bad = ~np.isfinite(arr)
        if bad.any():
            if arr.ndim == 0:
                raise ValueError(f"`{name}` must be finite, got {arr.item()!r}")
            index = tuple(int(i) for i in np.argwhere(bad)[0])
            raise ValueError(f"`{name}` contains NaN or inf at index {_fmt_index(index)}")
    return arr


def _real_scalar(value: Any, name: str) -> float:
    if type(value) is float and math.isfinite(value):  # the common case, at once
        return value
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__}")
    try:
        out = float(value)
    except OverflowError:  # an integer beyond the float range
        raise ValueError(
            f"`{name}` must be finite, got an integer beyond the float range"
        ) from None
    if not math.isfinite(out):
        raise ValueError(f"`{name}` must be finite, got {out!r}")
    return out


def finite_float(value: Any, name: str) -> float:
    """Return `value` as a finite Python float."""
    return _real_scalar(value, name)


def positive_float(value: Any, name: str) -> float:
    """Return `value` as a finite float > 0."""
    out = _real_scalar(value, name)
    if out <= 0.0:
        raise ValueError(f"`{name}` must be positive, got {out!r}")
    return out


def nonneg_float(value: Any, name: str) -> float:
    """Return `value` as a finite float >= 0."""
    out = _real_scalar(value, name)
    if out < 0.0:
        raise ValueError(f"`{name}` must be non-negative, got {out!r}")
    return out


def _int_scalar(value: Any, name: str) -> int:
    if type(value) is int:  # the common case, at once
        return value
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an integer, got {type(value).__name__}")
    return int(value)


#: Largest count (steps, iterations, a stride) the engine takes: what a 64-bit index holds
#: with room to spare.
MAX_COUNT = 2**53


def positive_int(value: Any, name: str, maximum: int = MAX_COUNT) -> int:
    """Return `value` (any Python or numpy integer) as a Python int in ``[1, maximum]``."""
    out = _int_scalar(value, name)
    if out < 1:
        raise ValueError(f"`{name}` must be a positive integer, got {out}")
    if out > maximum:
        raise ValueError(f"`{name}` must be at most {maximum:,}, got {out:,}")
    return out


def int_in_range(value: Any, name: str, lo: int, hi: int, meaning: str) -> int:
    """`value` (a Python or numpy integer; a float, even 2.0 or NaN, a string or a bool is a
    TypeError) as an int in ``[lo, hi]``; `meaning` says what it counts."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an integer ({meaning}), got {value!r}")
    out = int(value)
    if not lo <= out <= hi:
        raise ValueError(f"`{name}` must be {meaning}, {lo}..{hi}, got {out}")
    return out


def flag(value: Any, name: str) -> bool:
    """`value` as a bool: anything but True or False (a string 'no', 0, None) is a TypeError
    rather than taken by its truth value."""
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"`{name}` must be True or False, got {value!r}")
    return bool(value)


def _dof_range_error(name: str, n_dof: int, got: int) -> ValueError:
    return ValueError(
        f"`{name}` must be a degree-of-freedom index in [0, {n_dof - 1}] "
        f"(negative indices are not allowed), got {got}"
    )


def dof_index(value: Any, name: str, n_dof: int) -> int:
    """Return `value` as an int in ``[0, n_dof)``; negative (wrap-around) indices are rejected."""
    out = _int_scalar(value, name)
    if not 0 <= out < n_dof:
        raise _dof_range_error(name, n_dof, out)
    return out


def dof_list(value: Any, name: str, n_dof: int) -> NDArray[np.intp]:
    """Return `value` as a non-empty 1-D intp array of distinct indices in ``[0, n_dof)``."""
    if isinstance(value, str | bytes):
        raise TypeError(f"`{name}` must be a sequence of integers, got {type(value).__name__}")
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"`{name}` could not be converted to an array: {exc}") from None
    if arr.ndim != 1:
        raise ValueError(f"`{name}` must be a 1-D sequence of dof indices, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"`{name}` must contain at least one dof index")
    if arr.dtype.kind not in "iu":
        raise TypeError(f"`{name}` must contain integers, got dtype {_kind_name(arr.dtype)}")
    bad = np.flatnonzero((arr < 0) | (arr >= n_dof))
    if bad.size:
        raise _dof_range_error(f"{name}[{bad[0]}]", n_dof, int(arr[bad[0]]))
    uniq, counts = np.unique(arr, return_counts=True)
    if uniq.size != arr.size:
        raise ValueError(f"`{name}` contains duplicate dof index {int(uniq[counts > 1][0])}")
    return np.ascontiguousarray(arr, dtype=np.intp)


def mode_count(value: Any, name: str, n_dof: int) -> int:
    """Return the number of modes: ``None`` -> `n_dof`, else an int in ``[1, n_dof]``."""
    if value is None:
        return n_dof
    out = _int_scalar(value, name)
    if not 1 <= out <= n_dof:
        raise ValueError(f"`{name}` must be an integer in [1, n_dof] = [1, {n_dof}], got {out}")
    return out


# --------------------------------------------------------------------------------------------
# Matrices (dense ndarray or scipy.sparse CSR)
# --------------------------------------------------------------------------------------------


def issparse(value: Any) -> bool:
    """Whether `value` is a scipy.sparse matrix or array, without importing scipy.sparse.

    A caller cannot hold a sparse matrix without having imported ``scipy.sparse``, so when it
    is not in ``sys.modules`` the answer is False (and ``import duhamel`` stays scipy-free).
    While another thread is still importing it (runs in parallel threads, e.g.
    :func:`duhamel.ensemble.solve_many`) the module is there without its functions: the
    import statement then waits for that import to finish.
    """
    sparse = sys.modules.get("scipy.sparse")
    if sparse is None:
        return False
    if not hasattr(sparse, "issparse"):  # partially initialised by another thread
        import scipy.sparse as sparse
    return bool(sparse.issparse(value))


def as_square_matrix(
    value: Any, name: str, n: int | None = None, ref: str | None = None
) -> NDArray[np.float64] | Any:
    """Validate a square, real, finite matrix.

    Dense input becomes a C-contiguous float64 ndarray; scipy.sparse input becomes a float64
    CSR matrix/array of the same flavour (``csr_matrix`` or ``csr_array``), duplicates summed.
    If `n` is given the shape must be ``(n, n)`` (`ref` names the matrix it must match).
    """
    if issparse(value):
        _check_real_dtype(value.dtype, name)
        if len(value.shape) != 2:
            raise ValueError(f"`{name}` must be a 2-D matrix, got shape {value.shape}")
        mat = value.tocsr(copy=True).astype(np.float64, copy=False)
        mat.sum_duplicates()
        bad = np.flatnonzero(~np.isfinite(mat.data))
        if bad.size:
            row = int(np.searchsorted(mat.indptr, bad[0], side="right") - 1)
            col = int(mat.indices[bad[0]])
            raise ValueError(f"`{name}` contains NaN or inf at index ({row}, {col})")
    else:
        mat = as_float_array(value, name, ndim=2)
    shape = tuple(int(s) for s in mat.shape)
    if shape[0] != shape[1]:
        raise ValueError(f"`{name}` must be a square matrix, got shape {shape}")
    if n is not None and shape != (n, n):
        against = f" to match `{ref}`" if ref else ""
        raise ValueError(f"`{name}` must have shape ({n}, {n}){against}, got {shape}")
    return mat


def check_symmetric(mat: Any, name: str, rtol: float = 1e-10) -> None:
    """Raise ValueError unless ``max|A - A.T| <= rtol * max|A|``."""
    if issparse(mat):
        asym = float(abs(mat - mat.T).max()) if mat.nnz else 0.0
        scale = float(abs(mat).max()) if mat.nnz else 0.0
    else:
        asym = float(np.max(np.abs(mat - mat.T))) if mat.size else 0.0
        scale = float(np.max(np.abs(mat))) if mat.size else 0.0
    if asym > rtol * scale:
        hint = ""
        if issparse(mat):
            import scipy.sparse as sp

            if sp.triu(mat, k=1).nnz == 0 or sp.tril(mat, k=-1).nnz == 0:
                hint = (
                    f" (it stores one triangle only, as some FE exports do: pass "
                    f"{name} + {name}.T - scipy.sparse.diags({name}.diagonal()))"
                )
        raise ValueError(
            f"`{name}` must be symmetric: max |{name} - {name}.T| = {asym:.3g} exceeds "
            f"{rtol:g} * max |{name}| = {rtol * scale:.3g}{hint}"
        )


def _diagonal(mat: Any) -> NDArray[np.float64]:
    return np.asarray(mat.diagonal(), dtype=np.float64)


def check_nonneg_diagonal(mat: Any, name: str) -> None:
    """Cheap necessary condition for positive semidefiniteness: no negative diagonal entry."""
    diag = _diagonal(mat)
    bad = np.flatnonzero(diag < 0.0)
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"`{name}` must be positive semidefinite, but {name}[{i}, {i}] = {diag[i]:.6g} < 0"
        )


def symmetric_lu(mat: Any) -> tuple[Any, int]:
    """Sparse LDL^T-style factorisation of a symmetric matrix, with its inertia.

    SuperLU runs with a symmetric fill-reducing ordering and no row pivoting, so the diagonal
    of ``U`` holds the pivots of ``P A P^T = L D L^T``. By Sylvester's law of inertia their
    signs are the signs of the eigenvalues of `mat`. Returns ``(lu, n_bad)`` where `n_bad`
    counts non-positive pivots (at least 1 when a zero pivot forced a row exchange or the
    matrix is exactly singular, in which case `lu` is None); ``n_bad == 0`` means positive
    definite.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    try:
        lu = spla.splu(
            sp.csc_matrix(mat),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError:  # exactly singular
        return None, 1
    n_bad = int(np.count_nonzero(lu.U.diagonal() <= 0.0))
    if not np.array_equal(lu.perm_r, lu.perm_c):
        n_bad = max(n_bad, 1)
    return lu, n_bad


def check_positive_definite(mat: Any, name: str) -> None:
    """Raise ValueError unless the symmetric matrix `mat` is (numerically) positive definite.

    Dense input (and sparse input with n <= ``DENSE_CHOLESKY_MAX_N``) uses a dense Cholesky
    factorisation; larger sparse input uses a sparse LU with symmetric (fill-reducing)
    ordering and no row pivoting, i.e. an LDL^T factorisation whose pivots must all be > 0.
    Pivots smaller than ``SINGULAR_PIVOT_RTOL`` times their diagonal entry count as singular.
    """
    diag = _diagonal(mat)
    bad = np.flatnonzero(diag <= 0.0)
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"`{name}` must be positive definite, but {name}[{i}, {i}] = {diag[i]:.6g} "
            "is not positive"
        )
    n = diag.size
    not_pd = ValueError(f"`{name}` must be positive definite (its factorisation has a pivot <= 0)")
    if not issparse(mat) or n <= DENSE_CHOLESKY_MAX_N:
        import scipy.linalg

        dense = mat.toarray() if issparse(mat) else mat
        try:
            chol = scipy.linalg.cholesky(dense, lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            raise not_pd from None
        pivots = np.diagonal(chol) ** 2
    else:
        lu, n_bad = symmetric_lu(mat)
        if n_bad:
            raise not_pd
        pivots = lu.U.diagonal()[lu.perm_r]  # pivot of original row i
    ratio = pivots / diag
    if ratio.min() < SINGULAR_PIVOT_RTOL:
        raise ValueError(
            f"`{name}` must be positive definite, but it is singular to working precision "
            f"(relative pivot {ratio.min():.3g})"
        )


def check_mass(mat: Any, name: str = "M") -> None:
    """Raise ValueError unless the symmetric `mat` is positive semidefinite with its null
    space on whole dofs: a zero diagonal entry (a massless dof) with a zero row, and the block
    of the other dofs positive definite (:func:`check_positive_definite`). A negative
    diagonal entry, a nonzero entry in a massless row, or a singular block with mass is
    refused."""
    diag = _diagonal(mat)
    bad = np.flatnonzero(diag < 0.0)
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"`{name}` must be positive definite on the dofs with mass (and zero on massless "
            f"ones), but {name}[{i}, {i}] = {diag[i]:.6g} is negative"
        )
    zero = np.flatnonzero(diag == 0.0)
    if zero.size == 0:
        check_positive_definite(mat, name)
        return
    rows = abs(mat[zero]) if issparse(mat) else np.abs(np.asarray(mat)[zero])
    norms = np.asarray(rows.sum(axis=1)).ravel()
    if np.any(norms > 0.0):
        i = int(zero[np.argmax(norms > 0.0)])
        raise ValueError(
            f"`{name}` must be positive semidefinite, but its massless dof {i} ({name}[{i}, {i}]"
            f" = 0) has a nonzero entry in its row: `{name}` is indefinite"
        )
    if zero.size == diag.size:
        raise ValueError(f"`{name}` must have mass at some dof, but it is zero")
    keep = np.flatnonzero(diag > 0.0)
    sub = mat[keep][:, keep] if issparse(mat) else np.asarray(mat)[np.ix_(keep, keep)]
    try:
        check_positive_definite(sub, name)
    except ValueError:
        raise ValueError(
            f"`{name}` must be positive definite on its dofs with mass (a massless dof has a "
            "zero row and column), but that block is not"
        ) from None


def warn_heavy_damping(zeta: Any) -> None:
    """Warns (:class:`duhamel.DampingWarning`) when a damping ratio exceeds 1: often a
    percentage taken for a fraction (``zeta=5`` meant as 5 %)."""
    largest = float(np.max(zeta))
    if largest > 1.0:
        from duhamel.errors import DampingWarning

        warnings.warn(
            f"`zeta` = {largest:g} is above 1 ({100 * largest:g} % of critical damping): if you "
            f"meant {largest:g} %, pass {largest / 100:g}; if heavy damping is meant, silence "
            "this with warnings.simplefilter('ignore', duhamel.DampingWarning)",
            DampingWarning,
            stacklevel=3,
        )


def check_semidefinite(K: Any, rtol: float, *, shifted: tuple[float, float] | None = None) -> None:
    """Raises ValueError unless `K` (dense or sparse) is positive semidefinite to within
    `rtol` times its own largest entry: a Cholesky factorisation (sparse: the inertia of an
    LDL^T factorisation) of ``K + tau I``, ``tau = rtol max|K|``. A test of K alone, so an
    ill-conditioned mass matrix cannot hide a negative eigenvalue.

    ``shifted = (s, m)`` says that ``K + s M`` is already known to be positive definite (the
    inertia of the factorisation a sparse modal analysis made) and that ``|M|_2 <= m``. Then
    ``K + tau I >= K + s M > 0`` when ``s m <= tau``, and no factorisation is needed.
    """
    if issparse(K):
        import scipy.sparse as sp

        size = float(abs(K).max()) if K.nnz else 0.0
        if size == 0.0:
            return
        if shifted is not None and shifted[0] * shifted[1] <= rtol * size:
            return
        _, n_bad = symmetric_lu(sp.csc_matrix(K) + rtol * size * sp.identity(K.shape[0]))
        if n_bad:
            raise ValueError(
                f"`K` must be positive semidefinite, but K + {rtol:g} max|K| I has {n_bad} "
                "non-positive pivot(s), so K has a negative eigenvalue (the modal analysis "
                "would take it for a rigid-body mode): check the stiffness matrix's signs and "
                "assembly"
            )
        return
    size = float(np.max(np.abs(K))) if K.size else 0.0
    if size == 0.0:
        return  # no stiffness at all: every mode is a rigid-body mode
    try:
        np.linalg.cholesky(K + rtol * size * np.eye(K.shape[0]))
    except np.linalg.LinAlgError:
        low = float(np.linalg.eigvalsh(K)[0])
        raise ValueError(
            f"`K` must be positive semidefinite, but it has the eigenvalue {low:.6g} < 0 "
            "(the modal analysis would take it for a rigid-body mode): check the stiffness "
            "matrix's signs and assembly"
        ) from None
