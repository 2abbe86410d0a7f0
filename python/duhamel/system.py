"""Linear structural model ``M x'' + C x' + K x = f(t)`` and its undamped modal basis."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._validate import (
    as_float_array,
    as_square_matrix,
    check_nonneg_diagonal,
    check_positive_definite,
    check_semidefinite,
    check_symmetric,
    finite_float,
    issparse,
    mode_count,
    symmetric_lu,
    warn_heavy_damping,
)
from duhamel.elements import Element
from duhamel.loads import Load
from duhamel.mass import MassLaw, _Attached

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["ModalBasis", "System"]

DampingKind = Literal["none", "zeta", "rayleigh", "matrix"]
#: Eigenvalues below ``-NEG_EIG_RTOL * scale`` mean K is not positive semidefinite.
NEG_EIG_RTOL = 1e-9
#: Eigenvalues with ``omega2 <= ZERO_EIG_RTOL * scale`` are rigid-body modes, set to exactly 0.
ZERO_EIG_RTOL = 1e-12
#: Sparse shift-invert uses sigma = -SHIFT_RTOL * max(diag(K) / diag(M)): far enough below 0
#: for a reliable inertia check of K - sigma M, close enough for fast convergence.
SHIFT_RTOL = 1e-10
#: Relative size of off-diagonal modal damping terms above which C is "non-classical".
CLASSICAL_RTOL = 1e-8


@dataclass(frozen=True, eq=False)
class ModalBasis:
    """Mass-normalised undamped modes of a :class:`System` and their modal damping.

    Each modal coordinate obeys ``q_i'' + c_i q_i' + omega2_i q_i = phi_i^T f(t)``.
    All arrays are read-only float64.

    Attributes
    ----------
    phi : ndarray, shape (n_dof, n_modes)
        Mode shapes (C-contiguous), normalised so that ``phi.T @ M @ phi = I``. The entry of
        largest magnitude of each mode is positive (the first one, in case of near-ties).
    omega2 : ndarray, shape (n_modes,)
        Squared natural frequencies (rad/s)^2, ascending, >= 0. Rigid-body modes are exactly 0.
    omega : ndarray, shape (n_modes,)
        Natural frequencies ``sqrt(omega2)`` in rad/s.
    c : ndarray, shape (n_modes,)
        Modal damping per unit modal mass, the coefficient ``2 zeta omega`` of ``q'``. This is
        the authoritative damping value: for a rigid-body mode (``omega == 0``) the damping
        lives here only (e.g. ``c = alpha`` with Rayleigh damping ``(alpha, beta)``).
    zeta : ndarray, shape (n_modes,)
        Damping ratios ``c / (2 omega)`` where ``omega > 0``, else 0.0.
    c_coupling : ndarray, shape (n_modes, n_modes), or None
        For a damping matrix `C` that the undamped modes do not diagonalise (non-classical
        damping): the off-diagonal part of ``phi.T @ C @ phi``. The integrators keep the
        diagonal in the exact background and treat this remainder as a modal pseudo-force.
        None for classical damping.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.system import System
    >>> basis = System(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], zeta=0.05).modal()
    >>> basis.n_modes, basis.omega2.tolist()
    (2, [1.0, 3.0])
    >>> basis.zeta.tolist()
    [0.05, 0.05]
    """

    phi: NDArray[np.float64]
    omega2: NDArray[np.float64]
    omega: NDArray[np.float64]
    c: NDArray[np.float64]
    zeta: NDArray[np.float64]
    c_coupling: NDArray[np.float64] | None = None

    @property
    def n_modes(self) -> int:
        """Number of modes in the basis."""
        return int(self.omega2.shape[0])


def _frozen(a: NDArray[np.float64]) -> NDArray[np.float64]:
    out = np.ascontiguousarray(a, dtype=np.float64)
    if out is a:
        out = out.copy()
    out.setflags(write=False)
    return out


def _dense(a: Any) -> NDArray[np.float64]:
    return a.toarray() if issparse(a) else a


def _fix_signs(phi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Make the (first near-)largest-magnitude entry of each column positive."""
    mag = np.abs(phi)
    idx = np.argmax(mag >= (1.0 - 1e-6) * mag.max(axis=0), axis=0)
    signs = np.sign(phi[idx, np.arange(phi.shape[1])])
    signs[signs == 0.0] = 1.0
    return phi * signs


class System:
    """Linear structural model ``M x'' + C x' + K x = f(t)``.

    Parameters
    ----------
    M : array_like or scipy.sparse matrix, shape (n_dof, n_dof)
        Mass matrix: real, finite, symmetric, positive definite.
    K : array_like or scipy.sparse matrix, shape (n_dof, n_dof)
        Stiffness matrix: real, finite, symmetric, positive semidefinite (rigid-body modes
        are allowed; semidefiniteness is checked by the modal analysis).
    C : array_like or scipy.sparse matrix, shape (n_dof, n_dof), optional
        Viscous damping matrix (real, finite, symmetric). Classical damping (diagonalised by
        the undamped modes) is integrated exactly; for non-classical damping the diagonal of
        its modal projection stays in the exact background and the rest enters as a modal
        pseudo-force (see :class:`ModalBasis`).
    zeta : float or array_like, optional
        Modal damping ratio(s): one value for every mode, or one per mode of the modal
        basis (the length must then equal the number of modes used). May be negative.
    rayleigh : (float, float), optional
        Rayleigh coefficients ``(alpha, beta)`` for ``C = alpha M + beta K``.

    At most one of `C`, `zeta` and `rayleigh` may be given; with none the system is undamped.
    Dense matrices are stored as read-only float64 arrays, sparse ones as float64 CSR
    (never densified, except for a full dense eigensolve in :meth:`modal`).

    Attributes
    ----------
    loads : list
        Loads added with :meth:`add_load`.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.system import System
    >>> K = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]
    >>> system = System(np.eye(3), K, rayleigh=(0.1, 1e-3))
    >>> system
    System(n_dof=3, damping='rayleigh', loads=0)
    >>> np.round(system.modal().omega, 4).tolist()
    [0.445, 1.247, 1.8019]
    """

    def __init__(
        self,
        M: ArrayLike | sp.sparray | sp.spmatrix,
        K: ArrayLike | sp.sparray | sp.spmatrix,
        C: ArrayLike | sp.sparray | sp.spmatrix | None = None,
        *,
        zeta: float | ArrayLike | None = None,
        rayleigh: tuple[float, float] | None = None,
    ) -> None:
        given = [
            f"`{k}`" for k, v in (("C", C), ("zeta", zeta), ("rayleigh", rayleigh)) if v is not None
        ]
        if len(given) > 1:
            raise ValueError(
                f"pass at most one damping specification (`C`, `zeta` or `rayleigh`), "
                f"got {' and '.join(given)}"
            )
        M = as_square_matrix(M, "M")
        n = int(M.shape[0])
        if n == 0:
            raise ValueError("`M` must have at least one degree of freedom, got shape (0, 0)")
        K = as_square_matrix(K, "K", n=n, ref="M")
        check_symmetric(M, "M")
        check_symmetric(K, "K")
        check_positive_definite(M, "M")
        check_nonneg_diagonal(K, "K")
        self._M = M if issparse(M) else _frozen(M)
        self._K = K if issparse(K) else _frozen(K)
        self._C: Any = None
        self._zeta: float | NDArray[np.float64] | None = None
        self._rayleigh: tuple[float, float] | None = None
        self._damping: DampingKind = "none"
        if C is not None:
            C = as_square_matrix(C, "C", n=n, ref="M")
            check_symmetric(C, "C")
            self._C, self._damping = (C if issparse(C) else _frozen(C)), "matrix"
        elif zeta is not None:
            if np.ndim(zeta) == 0:
                self._zeta = finite_float(zeta, "zeta")
            else:
                z = as_float_array(zeta, "zeta", ndim=1)
                if not 1 <= z.size <= n:
                    raise ValueError(
                        f"`zeta` must have one entry per mode (between 1 and n_dof={n}), "
                        f"got {z.size}"
                    )
                self._zeta = _frozen(z)
            warn_heavy_damping(self._zeta)
            self._damping = "zeta"
        elif rayleigh is not None:
            alpha, beta = as_float_array(rayleigh, "rayleigh", shape=(2,)).tolist()
            self._rayleigh, self._damping = (alpha, beta), "rayleigh"
        self.loads: list[Load] = []
        #: Force elements (nonlinear springs, dampers, couplings, contacts), see :meth:`add`.
        self.elements: list[Element] = []
        #: Time-varying mass law, see :meth:`set_mass_law` (None: constant mass).
        self.mass_law: Any = None
        self._modal_cache: dict[int, ModalBasis] = {}

    # ---------------------------------------------------------------- properties
    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        return int(self._M.shape[0])

    @property
    def M(self) -> Any:
        """Mass matrix (read-only float64 ndarray or float64 CSR sparse matrix)."""
        return self._M

    @property
    def K(self) -> Any:
        """Stiffness matrix (read-only float64 ndarray or float64 CSR sparse matrix)."""
        return self._K

    @property
    def C(self) -> Any:
        """Damping matrix, or ``None`` when damping is not given as a matrix."""
        return self._C

    @property
    def zeta(self) -> float | NDArray[np.float64] | None:
        """Modal damping ratio(s) as given, or ``None``."""
        return self._zeta

    @property
    def rayleigh(self) -> tuple[float, float] | None:
        """Rayleigh coefficients ``(alpha, beta)`` as given, or ``None``."""
        return self._rayleigh

    @property
    def damping(self) -> DampingKind:
        """How damping was specified: ``'none'``, ``'zeta'``, ``'rayleigh'`` or ``'matrix'``."""
        return self._damping

    @property
    def is_sparse(self) -> bool:
        """Whether `M` or `K` is stored as a scipy.sparse matrix."""
        return issparse(self._M) or issparse(self._K)

    def __repr__(self) -> str:
        return (
            f"System(n_dof={self.n_dof}, damping={self._damping!r}, loads={len(self.loads)}"
            + (f", elements={len(self.elements)}" if self.elements else "")
            + (", mass_law" if self.mass_law is not None else "")
            + ")"
        )

    # ---------------------------------------------------------------- loads
    def add_load(self, load: Load) -> System:
        """Append a load to :attr:`loads`, validating it against this system first.

        The load is checked against this system here, so that, e.g., an out-of-range dof
        raises now rather than at solve time.

        Returns
        -------
        System
            ``self``, so calls can be chained.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> system = duhamel.System(np.eye(2), np.eye(2))
        >>> len(system.add_load(duhamel.loads.Step(dof=1, amplitude=5.0)).loads)
        1
        """
        if not isinstance(load, Load):
            raise TypeError(
                f"`load` must be a duhamel.loads load (Step, Harmonic, Tabulated, "
                f"BaseAcceleration, Unbalance, Callable), got {type(load).__name__}"
            )
        load._validate(self)
        self.loads.append(load)
        return self

    def add(self, element: Element) -> System:
        """Append a force element (see :mod:`duhamel.elements`), validated against this system.

        Elements add a restoring force ``r(x, x', t)`` to the left-hand side,
        ``M x'' + C x' + K x + r = f(t)``; the integrators treat it as a modal pseudo-force.

        Returns
        -------
        System
            ``self``, so calls can be chained.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> duffing = duhamel.System(np.eye(1), np.eye(1)).add(duhamel.elements.Cubic(0, 4.0))
        >>> len(duffing.elements)
        1
        """
        if not isinstance(element, Element):
            raise TypeError(
                f"`element` must be a duhamel.elements element, got {type(element).__name__}"
            )
        element._validate(self)
        self.elements.append(element)
        return self

    def set_mass_law(
        self, law: Any, *, form: str = "acceleration", scale_stiffness: bool = False
    ) -> System:
        """Make the mass time-varying: ``M(t) = M mu(t)`` for a law of :mod:`duhamel.mass`.

        Parameters
        ----------
        law : duhamel.mass law
            ``Exponential``, ``Harmonic`` or ``Tabulated``.
        form : {"acceleration", "momentum"}
            ``M(t) x''``, or ``d/dt (M(t) x')`` as in the paper's eqs. 28 and 35.
        scale_stiffness : bool
            Whether the stiffness scales with the mass too (gravity stiffness, e.g. the
            pendulum's ``m g / l``).

        Returns
        -------
        System
            ``self``.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> pendulum = duhamel.System(np.eye(1), np.eye(1)).set_mass_law(
        ...     duhamel.mass.Exponential(rate=-0.1), form="momentum", scale_stiffness=True)
        >>> pendulum.mass_law.form
        'momentum'
        """
        if not isinstance(law, MassLaw):
            raise TypeError(f"`law` must be a duhamel.mass law, got {type(law).__name__}")
        if form not in ("acceleration", "momentum"):
            raise ValueError(f"`form` must be 'acceleration' or 'momentum', got {form!r}")
        if not isinstance(scale_stiffness, bool | np.bool_):
            raise TypeError(f"`scale_stiffness` must be a bool, got {scale_stiffness!r}")
        self.mass_law = _Attached(law, form, bool(scale_stiffness))
        return self

    # ---------------------------------------------------------------- modal analysis
    def modal(self, n_modes: int | None = None) -> ModalBasis:
        """Undamped modal analysis ``K phi = omega^2 M phi`` (cached per `n_modes`).

        Parameters
        ----------
        n_modes : int, optional
            Number of lowest modes to keep, in ``[1, n_dof]``; default all (error messages
            call it `modes`, the integrator option that feeds it). Sparse systems
            with ``n_modes < n_dof - 1`` use shift-invert Lanczos (``eigsh``) with a small
            negative shift, so singular `K` (rigid-body modes) is fine; otherwise a dense
            ``scipy.linalg.eigh`` is used.

        Returns
        -------
        ModalBasis
            Mass-normalised modes, ``omega2``/``omega`` and modal damping ``c``/``zeta``.

        Raises
        ------
        ValueError
            If `K` is not positive semidefinite or `zeta` has the wrong length.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.system import System
        >>> free_free = System(np.eye(2), [[1.0, -1.0], [-1.0, 1.0]], rayleigh=(0.5, 0.0))
        >>> basis = free_free.modal()
        >>> basis.omega2.tolist(), basis.c.tolist(), np.round(basis.zeta, 4).tolist()
        ([0.0, 2.0], [0.5, 0.5], [0.0, 0.1768])
        """
        n = mode_count(n_modes, "modes", self.n_dof)  # user-facing name (integrators)
        cached = self._modal_cache.get(n)
        if cached is None:
            cached = self._modal_cache[n] = self._compute_modal(n)
        return cached

    def _eigen(self, n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        import scipy.linalg  # here, not at module level: `import duhamel` stays scipy-free

        if self.is_sparse and n < self.n_dof - 1:
            import scipy.sparse as sp
            import scipy.sparse.linalg as spla

            M, K = sp.csc_matrix(self._M), sp.csc_matrix(self._K)
            shift = float(np.max(np.abs(K.diagonal()) / M.diagonal()))  # <= max eigenvalue
            sigma = -SHIFT_RTOL * (shift if shift > 0.0 else 1.0)
            # A negative pivot of K - sigma M means K has an eigenvalue below sigma < 0, which
            # the shift-invert iteration (eigenvalues nearest sigma) could otherwise miss.
            lu, n_bad = symmetric_lu(K - sigma * M)
            if n_bad:
                raise ValueError(
                    f"`K` must be positive semidefinite, but K - sigma M (sigma = {sigma:.3g}) "
                    "has a non-positive pivot, so K has an eigenvalue below sigma"
                )
            op_inv = spla.LinearOperator(K.shape, matvec=lu.solve, dtype=np.float64)
            _, phi = spla.eigsh(K, k=n, M=M, sigma=sigma, which="LM", OPinv=op_inv)
            # Rayleigh-Ritz on the converged subspace: exact M-orthonormality, sorted output.
            kr, mr = phi.T @ (K @ phi), phi.T @ (M @ phi)
            lam, y = scipy.linalg.eigh((kr + kr.T) / 2, (mr + mr.T) / 2)
            return lam, phi @ y
        return scipy.linalg.eigh(
            _dense(self._K), _dense(self._M), subset_by_index=[0, n - 1], check_finite=False
        )

    def _compute_modal(self, n: int) -> ModalBasis:
        lam, phi = self._eigen(n)
        phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, self._M @ phi))
        ratio = np.abs(self._K.diagonal()) / self._M.diagonal()
        scale = max(float(np.max(np.abs(lam))), float(np.max(ratio)))
        if lam[0] < -NEG_EIG_RTOL * scale:
            raise ValueError(
                f"`K` must be positive semidefinite, but the modal analysis found "
                f"omega^2 = {lam[0]:.6g} < 0 (tolerance {NEG_EIG_RTOL:g} * {scale:.6g})"
            )
        if lam[0] <= ZERO_EIG_RTOL * scale:
            # A zero eigenvalue is a rigid-body mode only if K is semidefinite; an
            # ill-conditioned M inflates `scale` and can hide a negative one (Sylvester).
            check_semidefinite(self._K, NEG_EIG_RTOL)
        lam = np.where(lam <= ZERO_EIG_RTOL * scale, 0.0, lam)
        if self._damping == "matrix":
            lam, phi, c = self._classical_damping(lam, phi, scale)
        elif self._damping == "rayleigh":
            alpha, beta = self._rayleigh  # type: ignore[misc]
            c = alpha + beta * lam
        elif self._damping == "zeta":
            z = self._zeta
            if isinstance(z, np.ndarray) and z.size != n:
                raise ValueError(
                    f"`zeta` has {z.size} entries but the modal basis has {n} modes; "
                    "pass one damping ratio per retained mode"
                )
            c = 2.0 * np.asarray(z) * np.sqrt(lam)
        else:
            c = np.zeros(n)
        phi = _fix_signs(phi)
        coupling = None
        if self._damping == "matrix":
            cm = phi.T @ (self._C @ phi)
            cm = (cm + cm.T) / 2
            c = np.diag(cm).copy()
            off = cm - np.diag(c)
            ref = max(float(np.max(np.abs(c))), np.finfo(float).tiny)
            if n > 1 and float(np.max(np.abs(off))) > CLASSICAL_RTOL * ref:
                coupling = _frozen(off)
        omega = np.sqrt(lam)
        zeta = np.divide(c, 2.0 * omega, out=np.zeros(n), where=omega > 0.0)
        return ModalBasis(
            phi=_frozen(phi),
            omega2=_frozen(lam),
            omega=_frozen(omega),
            c=_frozen(np.broadcast_to(c, (n,))),
            zeta=_frozen(zeta),
            c_coupling=coupling,
        )

    def _classical_damping(
        self, lam: NDArray[np.float64], phi: NDArray[np.float64], scale: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Project C onto the modes, rotating within degenerate clusters so that a classical C
        comes out diagonal there; a non-classical remainder is kept by the caller."""

        def project(p: NDArray[np.float64]) -> NDArray[np.float64]:
            cm = p.T @ (self._C @ p)
            return (cm + cm.T) / 2

        cm, lam, phi = project(phi), lam.copy(), phi.copy()
        n, i = lam.size, 0
        while i < n:  # modes of (numerically) equal frequency may be mixed freely
            j = i
            while j + 1 < n and lam[j + 1] - lam[j] <= 1e-8 * lam[j + 1] + 1e-13 * scale:
                j += 1
            if j > i:
                import scipy.linalg

                _, y = scipy.linalg.eigh(cm[i : j + 1, i : j + 1])
                phi[:, i : j + 1] = phi[:, i : j + 1] @ y
                lam[i : j + 1] = lam[i : j + 1].mean()
            i = j + 1
        diag = np.diag(project(phi))
        return lam, phi, diag.copy()
