"""ROSS interoperability: a duhamel System from a ROSS ``Rotor`` (optional extra ``[ross]``).

`ROSS <https://github.com/petrobras/ross>`_ (PyPI ``ross-rotordynamics``) assembles rotor models
with 6 degrees of freedom per node, ``(x, y, z, alpha, beta, theta)``, and integrates them with
a Python-level Newmark loop or ``scipy.signal.lsim``. :func:`from_ross` takes ROSS's global
matrices ``M``, ``K``, ``C`` and ``G`` of ``M x'' + (C + speed G) x' + K x = f`` at one speed,
keeps the lateral dofs and returns a :class:`duhamel.System` for any duhamel integrator, with a
:class:`RossDofs` map between ROSS's dof numbering and the System's. See docs/ross.md.

ROSS is imported only by the caller (it is never imported here); any object with ROSS's
``M``, ``K``, ``C``, ``G`` methods and elements carrying ``dof_global_index`` works.
"""

from __future__ import annotations

import inspect
import re
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float
from duhamel.loads import Load, Tabulated
from duhamel.loads import Unbalance as UnbalanceLoad
from duhamel.rotor._speed import constant_speed
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.transient import add_couplings, nonzero, storage
from duhamel.system import System

__all__ = ["RossDofs", "RossModel", "from_ross"]

#: ROSS's local dof names, in its per-node order.
ROSS_DIRECTIONS = ("x", "y", "z", "alpha", "beta", "theta")
#: The lateral dofs duhamel keeps, and their duhamel names (no sign change).
LATERAL = ("x", "y", "alpha", "beta")
DUHAMEL_NAMES = {"x": "x", "y": "y", "theta_x": "alpha", "theta_y": "beta"}
#: Couplings between the kept lateral dofs and the dropped axial/torsional ones larger than
#: this, relative to the largest entry of the matrix, refuse the reduction.
COUPLING_RTOL = 1e-12
_LABEL = re.compile(r"^([a-z]+)_(\d+)$")


@dataclass(frozen=True, eq=False)
class RossDofs:
    """Map between a ROSS rotor's global dofs and the degrees of freedom of a duhamel System.

    System dof ``i`` is ROSS's global dof ``ross_index[i]``, named ``labels[i]`` in ROSS's
    element ``dof_global_index`` (``"x_3"``: x of node 3). The System keeps ROSS's order, so for
    shaft node ``n`` of a ROSS 6-dof model the System's dofs ``4n .. 4n + 3`` are
    ``(x, y, alpha, beta)`` = duhamel's ``(x, y, theta_x, theta_y)`` (also for point-mass and
    support nodes, which only have ``x`` and ``y`` after the ROSS shaft nodes).

    Attributes
    ----------
    ross_index : ndarray of int, shape (n_dof,)
        ROSS global index of each System dof (ascending).
    labels : tuple of str
        ROSS name of each System dof.
    n_ross : int
        Number of dofs of the ROSS model (``rotor.ndof``), the dropped ones included.
    """

    ross_index: NDArray[np.intp]
    labels: tuple[str, ...]
    n_ross: int

    def __post_init__(self) -> None:
        lookup = {label: i for i, label in enumerate(self.labels)}
        object.__setattr__(self, "_lookup", lookup)
        inverse = np.full(self.n_ross, -1, dtype=np.intp)
        inverse[self.ross_index] = np.arange(self.ross_index.size)
        inverse.setflags(write=False)
        object.__setattr__(self, "_inverse", inverse)

    @property
    def n_dof(self) -> int:
        """Number of System dofs."""
        return int(self.ross_index.size)

    def index(self, node: int, direction: str) -> int:
        """System dof of ROSS node `node`, `direction` ``"x"``, ``"y"``, ``"alpha"`` (=
        ``"theta_x"``) or ``"beta"`` (= ``"theta_y"``).

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor.ross import RossDofs
        >>> dofs = RossDofs(np.array([0, 1, 3, 4]), ("x_0", "y_0", "alpha_0", "beta_0"), 6)
        >>> dofs.index(0, "y"), dofs(0, "theta_y"), dofs.system_index(3)
        (1, 3, 2)
        """
        if isinstance(node, bool) or not isinstance(node, int | np.integer):
            raise TypeError(f"`node` must be an integer, got {type(node).__name__}")
        name = DUHAMEL_NAMES.get(direction, direction)
        if name in ("z", "theta"):
            raise ValueError(
                f"`direction` {direction!r} is an axial/torsional dof, which from_ross drops "
                "(it keeps the lateral dofs x, y, alpha, beta)"
            )
        if name not in LATERAL:
            raise ValueError(
                f"`direction` must be one of 'x', 'y', 'alpha' ('theta_x'), 'beta' "
                f"('theta_y'), got {direction!r}"
            )
        label = f"{name}_{int(node)}"
        found = self._lookup.get(label)  # type: ignore[attr-defined]
        if found is None:
            raise ValueError(f"the ROSS model has no dof {label!r} (node {node}, {direction!r})")
        return int(found)

    __call__ = index

    def system_index(self, ross_dof: int) -> int:
        """System dof of ROSS global dof `ross_dof` (ValueError for a dropped dof)."""
        if isinstance(ross_dof, bool) or not isinstance(ross_dof, int | np.integer):
            raise TypeError(f"`ross_dof` must be an integer, got {type(ross_dof).__name__}")
        if not 0 <= ross_dof < self.n_ross:
            raise ValueError(f"`ross_dof` must be in [0, {self.n_ross - 1}], got {ross_dof}")
        out = int(self._inverse[ross_dof])  # type: ignore[attr-defined]
        if out < 0:
            raise ValueError(f"ROSS dof {ross_dof} is axial or torsional: from_ross drops it")
        return out

    def from_ross(self, values: ArrayLike) -> NDArray[np.float64]:
        """Select the System's dofs from an array over ROSS's dofs (last axis ``n_ross``),
        e.g. ROSS's force array ``F`` or a response ``yout``."""
        a = np.asarray(values, dtype=np.float64)
        if a.ndim == 0 or a.shape[-1] != self.n_ross:
            raise ValueError(
                f"`values` must have ROSS's {self.n_ross} dofs on its last axis, got shape "
                f"{a.shape}"
            )
        return a[..., self.ross_index]

    def to_ross(self, values: ArrayLike) -> NDArray[np.float64]:
        """Spread an array over the System's dofs (last axis ``n_dof``) onto ROSS's dofs,
        zero on the dropped axial and torsional dofs (e.g. ``sol.x`` beside ROSS's ``yout``)."""
        a = np.asarray(values, dtype=np.float64)
        if a.ndim == 0 or a.shape[-1] != self.n_dof:
            raise ValueError(
                f"`values` must have the System's {self.n_dof} dofs on its last axis, got "
                f"shape {a.shape}"
            )
        out = np.zeros((*a.shape[:-1], self.n_ross))
        out[..., self.ross_index] = a
        return out

    def loads(self, F: ArrayLike, t: ArrayLike) -> list[Load]:
        """ROSS's force array as duhamel loads: one :class:`duhamel.loads.Tabulated` (linear
        between the samples, as ROSS's ``lsim`` path) per System dof with a nonzero force.

        Parameters
        ----------
        F : array_like, shape (len(t), n_ross)
            Force on every ROSS dof at the times `t` (ROSS's ``run_time_response`` input).
        t : array_like, shape (n_t,)
            Increasing sample times.

        Raises
        ------
        ValueError
            For a nonzero force on a dropped (axial or torsional) dof.
        """
        ts = as_float_array(t, "t", ndim=1)
        f = as_float_array(F, "F", ndim=2)
        if f.shape != (ts.size, self.n_ross):
            raise ValueError(
                f"`F` must have shape (len(t), n_ross) = ({ts.size}, {self.n_ross}), got {f.shape}"
            )
        dropped = np.ones(self.n_ross, dtype=bool)
        dropped[self.ross_index] = False
        bad = np.flatnonzero(dropped & np.any(f != 0.0, axis=0))
        if bad.size:
            raise ValueError(
                f"`F` loads ROSS dof {int(bad[0])}, an axial or torsional dof that from_ross drops"
            )
        return [Tabulated(i, ts, f[:, j]) for i, j in enumerate(self.ross_index) if np.any(f[:, j])]

    def unbalance(self, node: int, m_e: float, speed: Any, phase: float = 0.0) -> Load:
        """The unbalance ``m_e`` (kg m) at ROSS node `node` as a
        :class:`duhamel.loads.Unbalance`: ``m_e speed^2 (cos(speed t + phase), sin(speed t +
        phase))`` on the node's ``(x, y)``, the force of ROSS's unbalance response."""
        return UnbalanceLoad(self.index(node, "x"), self.index(node, "y"), m_e, speed, phase)


class RossModel(NamedTuple):
    """What :func:`from_ross` returns.

    Attributes
    ----------
    system : System
        The duhamel System (background, couplings; no loads).
    dofs : RossDofs
        ROSS dof <-> System dof.
    matrices : RotorMatrices
        The lateral ROSS matrices ``(M, K, C, G)`` of ``M x'' + (C + speed G) x' + K x = f``
        in System order (``K`` and ``C`` at `frequency`; ``G`` per unit speed).
    """

    system: System
    dofs: RossDofs
    matrices: RotorMatrices

    def unbalance_response(self, speeds: Any, unbalances: Any) -> Any:
        """Steady-state unbalance response (:func:`duhamel.rotor.unbalance_response`) with
        these matrices (ROSS's ``K`` and ``C`` at the model's `frequency`; for
        frequency-dependent bearings pass ``lambda w: from_ross(rotor, w).matrices`` to
        :func:`~duhamel.rotor.unbalance_response` instead), unbalances at ROSS nodes."""
        from duhamel.rotor.unbalance import unbalance_response

        return unbalance_response(self.matrices, speeds, unbalances, dof=self.dofs)


def _labels(rotor: Any) -> dict[int, str]:
    """ROSS global dof index -> name (``"x_3"``), from every element's ``dof_global_index``."""
    out: dict[int, str] = {}
    for element in rotor.elements:
        for name, index in element.dof_global_index.items():
            if not _LABEL.match(name) or name.split("_")[0] not in ROSS_DIRECTIONS:
                raise ValueError(f"unexpected ROSS dof name {name!r} in {type(element).__name__}")
            previous = out.setdefault(int(index), name)
            if previous != name:
                raise ValueError(f"ROSS dof {index} is named both {previous!r} and {name!r}")
    return out


def _evaluate(method: Any, frequency: float, speed: float) -> NDArray[np.float64]:
    """``method(frequency)``, with ``speed=`` where ROSS accepts it (ROSS >= 3)."""
    try:
        takes_speed = "speed" in inspect.signature(method).parameters
    except (TypeError, ValueError):  # pragma: no cover - builtins without a signature
        takes_speed = False
    out = method(frequency, speed=speed) if takes_speed else method(frequency)
    return np.asarray(out, dtype=np.float64)


def from_ross(
    rotor: Any,
    speed: Any,
    *,
    frequency: float | None = None,
    sparse: bool = False,
) -> RossModel:
    """A duhamel :class:`~duhamel.System` from a ROSS ``Rotor`` at constant `speed`.

    ROSS's global matrices ``M(frequency)``, ``K(frequency)``, ``C(frequency)`` (ROSS >= 3:
    with ``speed=speed``) and ``G()`` describe ``M x'' + (C + speed G) x' + K x = f`` on 6 dofs
    per node, ``(x, y, z, alpha, beta, theta)``. The lateral dofs ``(x, y, alpha, beta)`` are
    kept, in ROSS's order; they are duhamel's ``(x, y, theta_x, theta_y)`` **without any sign
    change** (ROSS's ``alpha`` is the rotation about +x, ``-dy/dz`` in bending, and ``beta``
    about +y, ``dx/dz``; its ``G`` has duhamel's sign: both give the same matrices for the same
    rotor to round-off). The axial ``z`` and torsional ``theta`` dofs are dropped, exactly as
    ROSS's ``convert_6dof_to_4dof``; ROSS's constant-speed matrices do not couple them to the
    lateral ones (checked: a coupling above 1e-12 of a matrix's largest entry raises). A model
    that already has 4 dofs per node, or one converted with ``convert_6dof_to_4dof``, is taken
    as it is.

    The System is built as :meth:`duhamel.rotor.Rotor.system` builds it:

    * background (exact in :class:`duhamel.Semianalytic`): ``M`` and ``K_sym = (K + K^T)/2``,
      with ``C = (C_ross + C_ross^T)/2`` as its damping matrix when that is nonzero (its
      modal diagonal is exact, the rest a pseudo-force);
    * ``LinearCoupling(C=speed * G)``: the gyroscopic terms (omitted at zero speed);
    * ``LinearCoupling(K=(K - K^T)/2, C=(C - C^T)/2)``: cross-coupled bearing and seal
      coefficients (omitted when zero).

    All damping is ROSS's ``C`` (bearings, seals, shaft ``alpha``/``beta`` damping); ROSS's
    example rotor has none, and neither does the System then.

    Parameters
    ----------
    rotor : ross.Rotor
        The ROSS model.
    speed : float
        Spin speed (rad/s), constant (a constant ``duhamel.speed`` law is accepted). ROSS's
        angular-acceleration stiffness ``Ksdt`` of a run-up is not mapped.
    frequency : float, optional
        Keyword only. Excitation frequency at which frequency-dependent bearing and seal
        coefficients are evaluated; default `speed`, as ROSS's ``run_time_response``.
    sparse : bool
        Keyword only. Store the matrices as ``scipy.sparse`` CSR (large models).

    Returns
    -------
    RossModel
        ``(system, dofs, matrices)``: the System (no loads: add them with
        ``system.add_load``, e.g. ``dofs.unbalance(...)`` or ``dofs.loads(F, t)``), the
        :class:`RossDofs` map, and the lateral ``(M, K, C, G)``.

    Raises
    ------
    ValueError
        If ``M`` is not symmetric, the lateral dofs are coupled to the dropped ones, or the
        dof names are not ROSS's. The System itself refuses a ``K_sym`` that is not positive
        semidefinite (a seal with a large negative direct stiffness) when it is solved.

    Examples
    --------
    ROSS's example rotor (6 shaft elements, 2 disks, 2 bearings; 7 nodes, 28 lateral dofs) at
    500 rad/s, with an unbalance and a rub at the disk of node 2:

    >>> import duhamel, ross                                            # doctest: +SKIP
    >>> from duhamel.rotor import from_ross
    >>> system, dofs, _ = from_ross(ross.rotor_example(), speed=500.0)  # doctest: +SKIP
    >>> system                                                          # doctest: +SKIP
    System(n_dof=28, damping='none', loads=0, elements=1)
    >>> dofs(2, "x"), dofs(2, "y"), dofs.labels[8:12]                   # doctest: +SKIP
    (8, 9, ('x_2', 'y_2', 'alpha_2', 'beta_2'))
    >>> _ = system.add_load(dofs.unbalance(2, m_e=1e-3, speed=500.0))   # doctest: +SKIP
    >>> rub = duhamel.elements.Contact(dofs(2, "x"), dofs(2, "y"),    # doctest: +SKIP
    ...                                clearance=8e-5, stiffness=5e7, friction=0.1)
    >>> _ = system.add(rub)                                             # doctest: +SKIP
    >>> sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=0.5, dt=1e-4)  # doctest: +SKIP
    >>> dofs.to_ross(sol.x).shape     # as ROSS's run_time_response(...).yout  # doctest: +SKIP
    (5001, 42)

    Without ROSS, anything with its interface does (here one rigid disk on two springs):

    >>> import numpy as np
    >>> class Disk:
    ...     dof_global_index = {"x_0": 0, "y_0": 1, "z_0": 2}
    >>> class Toy:                                      # a ROSS Rotor's interface
    ...     elements = [Disk()]
    ...     def M(self, f=None): return np.eye(3)
    ...     def K(self, f): return np.diag([1e4, 2e4, 5e3])
    ...     def C(self, f): return np.zeros((3, 3))
    ...     def G(self): return np.zeros((3, 3))
    >>> toy = Toy()
    >>> model = from_ross(toy, speed=0.0)
    >>> model.system.n_dof, model.dofs.labels, model.dofs(0, "y")
    (2, ('x_0', 'y_0'), 1)
    """
    w = constant_speed(speed)
    freq = w if frequency is None else finite_float(frequency, "frequency")
    for name in ("M", "K", "C", "G", "elements"):
        if not hasattr(rotor, name):
            raise TypeError(
                f"`rotor` must be a ROSS Rotor (it has no `{name}`), got {type(rotor).__name__}"
            )
    M = _evaluate(rotor.M, freq, w)
    K = _evaluate(rotor.K, freq, w)
    C = _evaluate(rotor.C, freq, w)
    G = np.asarray(rotor.G(), dtype=np.float64)
    n = M.shape[0]
    for name, a in (("M", M), ("K", K), ("C", C), ("G", G)):
        if a.shape != (n, n):
            raise ValueError(f"ROSS's `{name}` has shape {a.shape}, `M` has {M.shape}")

    labels = _labels(rotor)
    lateral = sorted(i for i, s in labels.items() if s.split("_")[0] in LATERAL)
    if len(labels) == n and sorted(labels) == list(range(n)):
        keep = np.asarray(lateral, dtype=np.intp)
        dropped = np.setdiff1d(np.arange(n), keep)
        for name, a in (("M", M), ("K", K), ("C", C), ("G", G)):
            scale = float(np.max(np.abs(a))) if a.size else 0.0
            c = np.abs(a[np.ix_(keep, dropped)]).max(initial=0.0)
            c = max(c, np.abs(a[np.ix_(dropped, keep)]).max(initial=0.0))
            if c > COUPLING_RTOL * scale:
                raise ValueError(
                    f"ROSS's `{name}` couples the lateral dofs to axial/torsional ones "
                    f"(|coupling| = {c:.3g}, {c / scale:.2e} of its largest entry); from_ross "
                    "keeps only the lateral dofs"
                )
        M, K, C, G = (a[np.ix_(keep, keep)] for a in (M, K, C, G))
        ross_index, n_ross = keep, n
    elif len(lateral) == n:  # convert_6dof_to_4dof: the matrices are the lateral block already
        ross_index, n_ross = np.arange(n, dtype=np.intp), n
    else:
        raise ValueError(
            f"ROSS's matrices have {n} dofs, but its elements name {len(labels)} dofs "
            f"({len(lateral)} lateral); cannot map them"
        )
    names = tuple(labels[i] for i in lateral)
    dofs = RossDofs(ross_index=ross_index, labels=names, n_ross=n_ross)
    if not np.allclose(M, M.T, rtol=0.0, atol=1e-12 * float(np.max(np.abs(M)))):
        raise ValueError("ROSS's mass matrix is not symmetric; a duhamel System needs it to be")
    M = (M + M.T) / 2.0
    for a in (M, K, C, G):
        a.setflags(write=False)
    matrices = RotorMatrices(M=M, K=K, C=C, G=G)

    conv = storage(sparse)
    k_sym, k_skew = (K + K.T) / 2.0, (K - K.T) / 2.0
    c_sym, c_skew = (C + C.T) / 2.0, (C - C.T) / 2.0
    if nonzero(c_sym):
        system = System(conv(M), conv(k_sym), conv(c_sym))
    else:
        system = System(conv(M), conv(k_sym))
    add_couplings(system, G, w, k_skew, c_skew, conv)
    if len(set(names)) == len(names):
        system.label_dofs(names)
    return RossModel(system=system, dofs=dofs, matrices=matrices)
