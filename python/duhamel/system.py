"""Linear structural model ``M x'' + C x' + K x = f(t)`` and its undamped modal basis."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._core import Element
from duhamel._engine import caches, shared
from duhamel._engine.basis import check_supplied, modal_basis, owned
from duhamel._engine.eigen import Modes
from duhamel._engine.geometric import softened
from duhamel._engine.labels import Labels, resolve, resolve_fields
from duhamel._engine.massless import Condensation
from duhamel._engine.validate import (
    as_square_matrix,
    check_mass,
    check_nonneg_diagonal,
    check_symmetric,
    issparse,
    mode_count,
    positive_float,
)
from duhamel.couplings import LinearCoupling
from duhamel.damping import DampingSummary, Rayleigh, damping_spec, damping_summary
from duhamel.elements.geometric import PDelta
from duhamel.loads import Load
from duhamel.mass import MassLaw, _Attached
from duhamel.modal import ModalBasis
from duhamel.modal import frozen as _frozen
from duhamel.modal_elements import STIFFNESS_DEFAULT, modal_with_elements

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["ModalBasis", "System"]

DampingKind = Literal["none", "zeta", "rayleigh", "matrix"]


class System:
    """Linear structural model ``M x'' + C x' + K x = f(t)``.

    Parameters
    ----------
    M : array_like or scipy.sparse matrix, shape (n_dof, n_dof)
        Mass matrix: real, finite, symmetric, positive definite. Any scipy.sparse format
        is taken, e.g. the COO matrix of ``scipy.io.mmread`` (a MatrixMarket export).
    K : array_like or scipy.sparse matrix, shape (n_dof, n_dof)
        Stiffness matrix: real, finite, symmetric, positive semidefinite (rigid-body modes
        are allowed; semidefiniteness is checked by the modal analysis).
    C : array_like or scipy.sparse matrix, shape (n_dof, n_dof), optional
        Viscous damping matrix (real, finite, symmetric). Classical damping (diagonalised by
        the undamped modes) is integrated exactly; for non-classical damping the diagonal of
        its modal projection stays in the exact background and the rest enters as a modal
        pseudo-force (see :class:`ModalBasis`).
    zeta : float, array_like or callable, optional
        Modal damping ratio(s): one value for every mode, one per mode of the modal
        basis (the length must then equal the number of modes used), or a function of the
        circular frequency ``zeta(omega)`` (vectorised). May be negative. The modes are those
        of the background a run integrates (see :meth:`damping_summary`).
    rayleigh : (float, float) or duhamel.Rayleigh, optional
        Rayleigh coefficients ``(alpha, beta)`` for ``C = alpha M + beta K``, or a
        :class:`duhamel.Rayleigh` (``Rayleigh.from_periods(T1, T2, zeta)``; restricted to a
        part of the model it becomes the damping matrix ``C``).

    At most one of `C`, `zeta` and `rayleigh` may be given; with none the system is undamped.
    Matrices are stored read-only (dense) or as float64 CSR (sparse, never densified).

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
        zeta: float | ArrayLike | Callable[[Any], Any] | None = None,
        rayleigh: tuple[float, float] | Rayleigh | None = None,
    ) -> None:
        M = as_square_matrix(M, "M")
        n = int(M.shape[0])
        if n == 0:
            raise ValueError("`M` must have at least one degree of freedom, got shape (0, 0)")
        K = as_square_matrix(K, "K", n=n, ref="M")
        self._content = shared.content_key(M, K)  # identical matrices: checked once
        if not shared.checked(self._content):
            check_symmetric(M, "M")
            check_symmetric(K, "K")
            check_mass(M, "M")
            check_nonneg_diagonal(K, "K")
            shared.remember_checked(self._content)
        self._M = M if issparse(M) else _frozen(M)
        self._K = K if issparse(K) else _frozen(K)
        # Massless dofs (zero rows of M): condensed exactly, a mechanism refused here.
        self._condensation = Condensation(self._M, self._K) if np.any(M.diagonal() == 0) else None
        self._C, self._zeta, self._rayleigh, self._damping = damping_spec(
            C, zeta, rayleigh, self._M, self._K
        )
        self._damping_given = rayleigh if isinstance(rayleigh, Rayleigh) else None
        self.loads: list[Load] = []
        #: Force elements (nonlinear springs, dampers, contacts, bearings), see :meth:`add`.
        self.elements: list[Element] = []
        #: Linear couplings (:class:`~duhamel.couplings.LinearCoupling`), apart from elements.
        self.couplings: list[LinearCoupling] = []
        #: Time-varying mass law, see :meth:`set_mass_law` (None: constant mass).
        self.mass_law: Any = None
        self._modal_cache: dict[int, ModalBasis] = {}
        self._modes = Modes(self._M, self._K, self._condensation)
        self._labels: tuple[str, ...] | None = None
        self._label_map: Labels | None = None
        #: P-Delta storeys taken into the stiffness (:class:`duhamel.elements.PDelta`).
        self.geometric: list[PDelta] = []

    # ---------------------------------------------------------------- properties
    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        return int(self._M.shape[0])

    @property
    def massless_dofs(self) -> NDArray[np.intp]:
        """Indices of the massless dofs (zero rows of `M`), condensed exactly: there is one
        mode per dof with mass (:attr:`n_mass`), and they follow the static relation.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> K = [[2.0, -1.0], [-1.0, 2.0]]
        >>> beam = duhamel.System(np.diag([1.0, 0.0]), K)
        >>> beam.massless_dofs.tolist(), beam.modal().n_modes
        ([1], 1)
        """
        c = self._condensation
        return np.zeros(0, dtype=np.intp) if c is None else c.s

    @property
    def n_mass(self) -> int:
        """Number of dofs with mass: the number of modes of the full modal basis."""
        c = self._condensation
        return self.n_dof if c is None else int(c.m.size)

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

    @property
    def dof_labels(self) -> tuple[str, ...] | None:
        """Names of the degrees of freedom (``None`` if not named), see :meth:`label_dofs`."""
        return self._labels

    def label_dofs(
        self, labels: Sequence[Hashable], *, aliases: Mapping[Hashable, int] | None = None
    ) -> System:
        """Name every dof (one distinct string or ``(node, component)`` pair each, in dof
        order; `aliases`, ``{label: index}``, names some twice). Labels then work wherever a
        dof index does (:meth:`dof`, elements and loads added afterwards, ``solve(...,
        dofs=)``) and in :meth:`~duhamel.Solution.to_xarray` (``(3, "ux")`` as ``"3:ux"``).
        Returns ``self``; ValueError if not one name per dof.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> duhamel.System(np.eye(2), np.eye(2)).label_dofs(["roof", "base"]).dof_labels
        ('roof', 'base')
        """
        self._label_map = Labels(list(labels), aliases, n_dof=self.n_dof)
        self._labels = self._label_map.texts
        return self

    def dof(self, label: Hashable, component: str | None = None) -> int:
        """The index of the dof named `label`; ``dof(3, "ux")`` is ``dof((3, "ux"))``.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> duhamel.System(np.eye(2), np.eye(2)).label_dofs([(3, "ux"), (3, "uy")]).dof(3, "uy")
        1
        """
        key = label if component is None else (label, component)
        if self._label_map is None:
            raise ValueError(f"`label` {key!r}: the system's dofs are not labelled")
        return self._label_map.index(key, "label")

    def __repr__(self) -> str:
        return (
            f"System(n_dof={self.n_dof}, damping={self._damping!r}, loads={len(self.loads)}"
            + (f", elements={len(self.elements)}" if self.elements else "")
            + (f", couplings={len(self.couplings)}" if self.couplings else "")
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
        load = resolve_fields(self, load)
        load._validate(self)
        self.loads.append(load)
        return self

    def add(self, element: Element | LinearCoupling | PDelta) -> System:
        """Append a force element (see :mod:`duhamel.elements`), validated against this system.

        Elements add a restoring force ``r(x, x', t)`` to the left-hand side,
        ``M x'' + C x' + K x + r = f(t)``; the integrators treat it as a modal pseudo-force.
        A :class:`~duhamel.couplings.LinearCoupling` is kept apart, in :attr:`couplings`.

        Returns
        -------
        System
            ``self``, so calls can be chained.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> duffing = duhamel.System(np.eye(1), np.eye(1)).add(duhamel.elements.Cubic(0, k3=4.0))
        >>> len(duffing.elements)
        1
        """
        if isinstance(element, Element):  # labels as dof indices
            element = element._resolved(lambda label, name: resolve(self, label, name))
        else:
            element = resolve_fields(self, element)
        if isinstance(element, PDelta):  # linear: part of the stiffness, exactly
            self.add_geometric_stiffness(element.matrix(self.n_dof))
            self.geometric.append(element)
            return self
        if not isinstance(element, Element | LinearCoupling):
            raise TypeError(
                f"`element` must be a duhamel.elements element, got {type(element).__name__}"
            )
        element._validate(self)
        if isinstance(element, LinearCoupling):
            self.couplings.append(element)
        else:
            self.elements.append(element)
        return self

    def add_geometric_stiffness(self, Kg: Any) -> System:
        """Take a geometric stiffness into the linear stiffness: `K` becomes ``K - Kg``.

        ``Kg``: the geometric stiffness of compressive gravity loads (``P / h`` per storey,
        :class:`duhamel.elements.PDelta`). Linear, so exact on every route (the modes see
        it). Refused (ValueError naming `Kg`) when not symmetric or when ``K - Kg`` is
        indefinite (the loads beyond the buckling load). The modes known so far are dropped.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]])
        >>> s.add_geometric_stiffness(0.1 * np.eye(2)).K.tolist()
        [[1.9, -1.0], [-1.0, 0.9]]
        """
        K = softened(self._K, Kg, self.n_dof)
        self._K = K if issparse(K) else _frozen(K)
        if self._condensation is not None:
            self._condensation = Condensation(self._M, self._K)
        self._modes = Modes(self._M, self._K, self._condensation)
        self._modal_cache = {}
        self._content = shared.content_key(self._M, self._K)
        caches.forget(self)
        return self

    def set_mass_law(
        self, law: Any, *, form: str = "acceleration", scale_stiffness: bool = False
    ) -> System:
        """Make the mass time-varying: ``M(t) = M mu(t)`` for a law of :mod:`duhamel.mass`;
        returns ``self``.

        Parameters
        ----------
        law : duhamel.mass law
            ``Exponential``, ``Harmonic`` or ``Tabulated``.
        form : {"acceleration", "momentum"}
            ``M(t) x''``, or ``d/dt (M(t) x')`` as in the paper's eqs. 28 and 35.
        scale_stiffness : bool
            Whether the stiffness scales with the mass too (gravity stiffness, e.g. the
            pendulum's ``m g / l``).

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

    def damping_summary(self, linear_parts: str = "auto") -> DampingSummary:
        """Each mode's damping ratio as ``Semianalytic(linear_parts=...)`` integrates this
        system: the modes of ``K`` (or of ``K`` plus the elements' linear parts under FNA's
        ``"background"``) and their ratios, from the first-order modes when the damping is
        non-classical (docs/structural.md, "Damping conventions").

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], rayleigh=(0.1, 0.0))
        >>> np.round(s.damping_summary().zeta, 4).tolist()
        [0.05, 0.0289]
        """
        return damping_summary(self, linear_parts)

    # ---------------------------------------------------------------- modal analysis
    def modal(self, n_modes: int | None = None, *, elements: str | None = None,
              displacement: float | None = None) -> ModalBasis:  # fmt: skip
        """Undamped modal analysis ``K phi = omega^2 M phi`` (cached per `n_modes`).

        Parameters
        ----------
        n_modes : int, optional
            Number of lowest modes to keep, in ``[1, n_dof]``; default all (errors call it
            `modes`). Sparse systems with ``n_modes < n_dof - 1`` use shift-invert Lanczos
            (singular `K` is fine), others a dense ``eigh``. Asking for more later computes
            only the additional ones; a basis given to :meth:`use_basis` is used instead.
        elements : {"initial", "effective"}, optional
            Default: the modes of ``K`` alone, as the integrators use them. ``"initial"``: of
            ``K`` plus the force elements' tangent at ``x = 0`` (OpenSees' ``eigen``; not
            symmetric: the real modes of the general problem, not mass-orthogonal);
            ``"effective"``: plus their ASCE 7 ``k_eff`` at `displacement`
            (:mod:`duhamel.modal_elements`). The basis's ``summary()`` says which.
        displacement : float, optional
            The amplitude of ``elements="effective"``.

        Returns
        -------
        ModalBasis
            Mass-normalised modes, ``omega2``/``omega`` and modal damping ``c``/``zeta``.

        Raises
        ------
        ValueError
            If `K` is not positive semidefinite, `zeta` has the wrong length, or a basis
            given to :meth:`use_basis` (without ``extend=True``) holds fewer modes.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> basis = duhamel.System(np.eye(2), [[1, -1], [-1, 1]], rayleigh=(0.5, 0.0)).modal()
        >>> basis.omega2.tolist(), basis.c.tolist(), np.round(basis.zeta, 4).tolist()
        ([0.0, 2.0], [0.5, 0.5], [0.0, 0.1768])
        """
        if elements is not None or displacement is not None:
            return modal_with_elements(self, n_modes, elements or "", displacement)
        n = mode_count(n_modes, "modes", self.n_mass)  # user-facing name (integrators)
        cached = self._modal_cache.get(n)
        if cached is None:
            cached = self._modal_cache[n] = modal_basis(self, n)
        said = STIFFNESS_DEFAULT if self.elements else ""  # what summary() states
        other = cached.labels is not self._labels or cached.mass is not self._M
        if other or cached.stiffness != said:  # a basis shared by the same matrices: ours
            cached = owned(cached, self._labels, self._M, said)
            self._modal_cache[n] = cached
        return cached

    def _with_stiffness(self, K: Any) -> System:
        """This model with the stiffness `K` (checked by the caller), no loads or elements."""
        other = object.__new__(System)
        other.__dict__.update(self.__dict__)  # (the engine's caches stay this model's)
        other._K = K if issparse(K) else _frozen(K)
        other.loads, other.elements, other.couplings, other.mass_law = [], [], [], None
        other._modal_cache = {}
        if self._condensation is not None:
            other._condensation = Condensation(self._M, other._K)
        other._modes = Modes(self._M, other._K, other._condensation)
        other._content = shared.content_key(self._M, other._K)
        return other

    def use_basis(self, basis: ModalBasis, *, extend: bool = False, rtol: float = 1e-6) -> System:
        """Use the undamped modes of `basis` instead of computing them.

        The basis may come from another system with the same `M` and `K` (its
        :meth:`modal`), from a file (:meth:`ModalBasis.load`) or from an FE package
        (:meth:`ModalBasis.from_modes`). Only its mode shapes and ``omega2`` are used: this
        system derives its own modal damping from them (`zeta`, `rayleigh` or `C`).

        Parameters
        ----------
        basis : ModalBasis
            Modes of this system's ``(K, M)``, the lowest ones, in ascending order.
        extend : bool
            When a run asks for more modes than `basis` holds: compute the additional ones
            (the lowest modes M-orthogonal to the given ones) if True, else raise ValueError.
        rtol : float
            Tolerance of the checks that `basis` belongs to this system: ``phi.T M phi = I``
            (largest entry error) and, for each mode, the relative residual
            ``|K phi - omega2 M phi| / ((|K| + omega2 |M|) |phi|)``.

        Returns
        -------
        System
            ``self``, so calls can be chained.

        Raises
        ------
        TypeError
            If `basis` is not a :class:`ModalBasis`.
        ValueError
            If its modes do not have this system's size or are not modes of its `M` and `K`.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> M, K = np.eye(3), [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]
        >>> basis = duhamel.System(M, K).modal(2)                  # computed once ...
        >>> shared = duhamel.System(M, K, zeta=0.05).use_basis(basis)  # ... shared
        >>> np.array_equal(shared.modal(2).phi, basis.phi), shared.modal(2).zeta.tolist()
        (True, [0.05, 0.05])
        """
        if not isinstance(basis, ModalBasis):
            raise TypeError(f"`basis` must be a duhamel.ModalBasis, got {type(basis).__name__}")
        if not isinstance(extend, bool | np.bool_):
            raise TypeError(f"`extend` must be a bool, got {extend!r}")
        rtol = positive_float(rtol, "rtol")
        check_supplied(self, basis, rtol)
        # a new store and cache: copies of this model keep theirs
        self._modes = Modes(self._M, self._K, self._condensation)
        self._modes.supply(basis.omega2, basis.phi, extend=bool(extend))
        self._modal_cache = {}
        return self
