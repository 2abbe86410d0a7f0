"""ROSS's lateral matrices and dof map: :class:`RossDofs` and :func:`lateral_matrices`
(used by :mod:`duhamel.rotor.ross.model` and :mod:`duhamel.rotor.ross.analyses`)."""

from __future__ import annotations

import inspect
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array
from duhamel.loads import Load, Tabulated
from duhamel.loads import Unbalance as UnbalanceLoad
from duhamel.rotor.assembly import RotorMatrices

__all__ = ["RossDofs", "lateral_matrices"]

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
        if name in ("z", "theta") and f"{name}_{int(node)}" not in self._lookup:  # type: ignore[attr-defined]
            raise ValueError(
                f"`direction` {direction!r} is an axial/torsional dof, which this model "
                "drops (from_ross keeps the lateral dofs x, y, alpha, beta unless "
                "dofs='all')"
            )
        if name not in ROSS_DIRECTIONS:
            raise ValueError(
                f"`direction` must be one of 'x', 'y', 'alpha' ('theta_x'), 'beta' "
                f"('theta_y'), 'z', 'theta', got {direction!r}"
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

    def from_ross(self, values: ArrayLike) -> NDArray[Any]:
        """Select the System's dofs from an array over ROSS's dofs (last axis ``n_ross``),
        e.g. ROSS's force array ``F`` or a response ``yout`` (complex amplitudes stay
        complex)."""
        a = _values(values)
        if a.ndim == 0 or a.shape[-1] != self.n_ross:
            raise ValueError(
                f"`values` must have ROSS's {self.n_ross} dofs on its last axis, got shape "
                f"{a.shape}"
            )
        return a[..., self.ross_index]

    def to_ross(self, values: ArrayLike) -> NDArray[Any]:
        """Spread an array over the System's dofs (last axis ``n_dof``) onto ROSS's dofs,
        zero on the dropped axial and torsional dofs (e.g. ``sol.x`` beside ROSS's ``yout``).
        Complex values (an unbalance response's amplitudes, mode shapes) stay complex.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor.ross import RossDofs
        >>> dofs = RossDofs(np.array([0, 1, 3, 4]), ("x_0", "y_0", "alpha_0", "beta_0"), 6)
        >>> dofs.to_ross(np.array([1.0, 1j, 0.0, 2.0])).tolist()
        [(1+0j), 1j, 0j, 0j, (2+0j), 0j]
        """
        a = _values(values)
        if a.ndim == 0 or a.shape[-1] != self.n_dof:
            raise ValueError(
                f"`values` must have the System's {self.n_dof} dofs on its last axis, got "
                f"shape {a.shape}"
            )
        out = np.zeros((*a.shape[:-1], self.n_ross), dtype=a.dtype)
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
        return [
            Tabulated(i, t=ts, values=f[:, j])
            for i, j in enumerate(self.ross_index)
            if np.any(f[:, j])
        ]

    def unbalance(self, node: int, m_e: float, speed: Any, phase: float = 0.0) -> Load:
        """The unbalance ``m_e`` (kg m) at ROSS node `node` as a
        :class:`duhamel.loads.Unbalance`: ``m_e speed^2 (cos(speed t + phase), sin(speed t +
        phase))`` on the node's ``(x, y)``, the force of ROSS's unbalance response."""
        return UnbalanceLoad(
            (self.index(node, "x"), self.index(node, "y")), m_e=m_e, speed=speed, phase=phase
        )


def _values(values: ArrayLike) -> NDArray[Any]:
    """`values` as float64, or complex128 when complex (never dropping an imaginary part)."""
    a = np.asarray(values)
    if np.iscomplexobj(a):
        return a.astype(np.complex128)
    return np.asarray(a, dtype=np.float64)


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


def lateral_matrices(
    rotor: Any, w: float, freq: float, every: bool = False
) -> tuple[RotorMatrices, RossDofs]:
    """ROSS's lateral ``(M, K, C, G)`` (``K``, ``C`` at `freq`, ROSS >= 3 also at speed `w`;
    without its magnetic bearings, whose closed loops replace them:
    :mod:`duhamel.rotor.ross.magnetic`) in System order, and the dof map; checks as
    :func:`from_ross` states; `every`: all of ROSS's dofs, axial and torsional too."""
    for name in ("M", "K", "C", "G", "elements"):
        if not hasattr(rotor, name):
            raise TypeError(
                f"`rotor` must be a ROSS Rotor (it has no `{name}`), got {type(rotor).__name__}"
            )
    from duhamel.rotor.ross.magnetic import without_magnetic

    M = _evaluate(rotor.M, freq, w)
    K, C = without_magnetic(rotor, _evaluate(rotor.K, freq, w), _evaluate(rotor.C, freq, w), freq)
    G = np.asarray(rotor.G(), dtype=np.float64)
    n = M.shape[0]
    for name, a in (("M", M), ("K", K), ("C", C), ("G", G)):
        if a.shape != (n, n):
            raise ValueError(f"ROSS's `{name}` has shape {a.shape}, `M` has {M.shape}")

    labels = _labels(rotor)
    kept = ROSS_DIRECTIONS if every else LATERAL
    lateral = sorted(i for i, s in labels.items() if s.split("_")[0] in kept)
    if every and len(labels) == n and sorted(labels) == list(range(n)):
        ross_index, n_ross = np.arange(n, dtype=np.intp), n
    elif len(labels) == n and sorted(labels) == list(range(n)):
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
    return RotorMatrices(M=M, K=K, C=C, G=G), dofs
