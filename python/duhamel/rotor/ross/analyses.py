"""A ROSS model with the analyses of a native :class:`~duhamel.rotor.Rotor`
(``from_ross(...).rotor``): modes, Campbell diagram, critical speeds, frequency and unbalance
responses, Level I stability, critical speed map, all on ROSS's lateral matrices re-evaluated
at each speed (``K(frequency=speed)``, ``C(frequency=speed)``, as ROSS's ``run_modal``,
``run_campbell`` and ``run_freq_response`` evaluate them)."""

from __future__ import annotations

import inspect
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel.rotor._analyses import RotorAnalyses
from duhamel.rotor._speed import constant_speed
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.critical_map import CriticalSpeedMap
from duhamel.rotor.ross.dofs import COUPLING_RTOL, RossDofs

__all__ = ["RossBearingCurve", "RossRotor"]


class RossBearingCurve:
    """A ROSS bearing's ``k..`` against speed through ROSS's own interpolants, its end values
    held beyond its frequencies (as a native bearing table's): the curve a critical speed map
    draws."""

    def __init__(self, element: Any) -> None:
        self.element = element
        self.node = int(element.n)
        freq = getattr(element, "frequency", None)
        f = np.atleast_1d(np.asarray(freq if freq is not None else [0.0], dtype=float))
        self._range = (float(f.min()), float(f.max()))

    def stiffness_at(self, speed: float) -> NDArray[np.float64]:
        """``[[kxx, kxy], [kyx, kyy]]`` at `speed` (rad/s)."""
        w = min(max(float(speed), self._range[0]), self._range[1])
        names = ("kxx", "kxy", "kyx", "kyy")
        k = [float(np.asarray(getattr(self.element, f"{n}_interpolated")(w))) for n in names]
        return np.array(k).reshape(2, 2)


def _parameters(method: Any) -> tuple[str, ...]:
    try:
        return tuple(inspect.signature(method).parameters)
    except (TypeError, ValueError):  # no method, or a builtin without a signature
        return ()


class RossRotor(RotorAnalyses):
    """A ROSS ``Rotor``'s lateral model with a native :class:`~duhamel.rotor.Rotor`'s analyses.

    Made by :attr:`RossModel.rotor <duhamel.rotor.RossModel.rotor>`; nodes and dofs are
    ROSS's (``dof(node, direction)`` is :class:`~duhamel.rotor.RossDofs`, the labels ROSS's
    ``"x_3"``, ``"alpha_3"``...).

    Parameters
    ----------
    source : ross.Rotor or None
        The ROSS model, asked for ``K`` and ``C`` at each speed; None: the fixed `matrices`.
    dofs : RossDofs
    matrices : RotorMatrices
        The matrices :func:`~duhamel.rotor.from_ross` read (used when `source` is None).

    Examples
    --------
    Anything with ROSS's interface (here one rigid disk on two springs):

    >>> import numpy as np
    >>> from duhamel.rotor import from_ross
    >>> class Disk:
    ...     dof_global_index = {"x_0": 0, "y_0": 1, "alpha_0": 2, "beta_0": 3}
    >>> class Toy:
    ...     elements = [Disk()]
    ...     def M(self, f=None): return np.diag([2.0, 2.0, 0.1, 0.1])
    ...     def K(self, f): return np.diag([8e4, 8e4, 1e4, 1e4])
    ...     def C(self, f): return np.zeros((4, 4))
    ...     def G(self): return np.zeros((4, 4))
    >>> model = from_ross(Toy(), speed=0.0)
    >>> np.round(model.rotor.natural_frequencies(0.0), 6).tolist()
    [200.0, 200.0, 316.227766, 316.227766]
    """

    journals: tuple[Any, ...] = ()
    has_speed_dependent_bearings = True

    def __init__(self, source: Any, dofs: RossDofs, matrices: RotorMatrices) -> None:
        self.source = source
        self.dofs = dofs
        self._fixed = matrices
        self.shafts = tuple(getattr(source, "shaft_elements", ()) or ())
        self._at = lru_cache(maxsize=64)(self._read)
        keep = dofs.ross_index
        dropped = np.setdiff1d(np.arange(dofs.n_ross), keep)
        self._blocks = (np.ix_(keep, keep), np.ix_(keep, dropped), np.ix_(dropped, keep))
        self._speed_kw = {
            name: "speed" in _parameters(getattr(source, name, None)) for name in ("M", "K", "C")
        }
        from duhamel.rotor.ross.magnetic import is_magnetic, magnetic_bearing

        #: ROSS's magnetic bearings as closed loops (:mod:`duhamel.rotor.ross.magnetic`).
        self.magnetic = tuple(
            magnetic_bearing(b) for b in getattr(source, "bearing_elements", ()) if is_magnetic(b)
        )

    @property
    def n_dof(self) -> int:  # type: ignore[override]
        """Number of lateral dofs."""
        return self.dofs.n_dof

    @property
    def dof_labels(self) -> tuple[str, ...]:  # type: ignore[override]
        """ROSS's name of each dof (``"x_0"``, ``"y_0"``, ``"alpha_0"``, ``"beta_0"``...)."""
        return self.dofs.labels

    @property
    def nodes_z(self) -> NDArray[np.float64]:  # type: ignore[override]
        """Axial positions of ROSS's nodes (``nodes_pos``)."""
        return np.asarray(getattr(self.source, "nodes_pos", []), dtype=float)

    def dof(self, node: int, direction: str) -> int:
        """System dof of ROSS node `node` (:meth:`RossDofs.index`)."""
        return self.dofs.index(node, direction)

    def _split(self) -> Any:
        """ROSS's matrices as constant parts plus the bearings' curves
        (:mod:`duhamel.rotor.ross.coefficients`), made on first use; None: read ROSS."""
        if not hasattr(self, "_split_made"):
            from duhamel.rotor.ross.coefficients import split
            from duhamel.rotor.ross.magnetic import is_magnetic

            made = None
            if not any(self._speed_kw.values()):
                elements = list(getattr(self.source, "bearing_elements", ()))
                made = split(
                    self.source,
                    self.dofs.ross_index,
                    [b for b in elements if not is_magnetic(b)],
                    [b for b in elements if is_magnetic(b)],
                )
            self._split_made = made
        return self._split_made

    def _read(self, w: float) -> RotorMatrices:
        """ROSS's ``M``, ``K``, ``C`` at ``frequency = speed = w`` (``G`` from from_ross),
        the lateral block, with from_ross's check that nothing couples it to the rest."""
        fast = self._split()
        if fast is not None:
            at = fast.at(w)
            return RotorMatrices((at["M"] + at["M"].T) / 2.0, at["K"], at["C"], self._fixed.G)
        keep, cross, back = self._blocks
        from duhamel.rotor.ross.magnetic import without_magnetic

        out = []
        full = {}
        for name in ("M", "K", "C"):
            method = getattr(self.source, name)
            full[name] = method(w, speed=w) if self._speed_kw[name] else method(w)
        full["K"], full["C"] = without_magnetic(self.source, full["K"], full["C"], w)
        for name in ("M", "K", "C"):
            a = np.asarray(full[name], dtype=float)
            if a.shape != (self.dofs.n_ross, self.dofs.n_ross):
                raise ValueError(f"ROSS's `{name}` at {w:g} rad/s has shape {a.shape}")
            c = max(np.abs(a[cross]).max(initial=0.0), np.abs(a[back]).max(initial=0.0))
            if c > COUPLING_RTOL * float(np.max(np.abs(a))):
                raise ValueError(
                    f"ROSS's `{name}` at {w:g} rad/s couples the lateral dofs to axial or "
                    "torsional ones; from_ross keeps only the lateral dofs"
                )
            out.append(a[keep])
        M, K, C = out
        return RotorMatrices((M + M.T) / 2.0, K, C, self._fixed.G)

    def matrices(self, speed: float = 0.0) -> RotorMatrices:  # type: ignore[override]
        """ROSS's lateral ``(M, K, C, G)`` with ``K`` and ``C`` at ``frequency = speed``."""
        w = constant_speed(speed)
        if self.source is None:
            return self._fixed
        return self._at(w)

    def _regular(self) -> bool:
        labels = self.dofs.labels
        return len(labels) % 4 == 0 and all(
            labels[4 * k + d] == f"{name}_{labels[4 * k].split('_')[1]}"
            for k in range(len(labels) // 4)
            for d, name in enumerate(("x", "y", "alpha", "beta"))
        )

    @property
    def layout(self) -> NDArray[np.intp] | None:  # type: ignore[override]
        """Per ROSS node (in the order its dofs come) the System dofs of ``(x, y, alpha,
        beta)`` and, with ``dofs="all"``, ``(z, theta)``; -1 where it has none (point masses
        and supports: x and y only); None when every node has all four in order."""
        if self._regular():
            return None
        names = ("x", "y", "alpha", "beta", "z", "theta")
        nodes: dict[str, list[int]] = {}
        for i, label in enumerate(self.dofs.labels):
            name, _, node = label.rpartition("_")
            nodes.setdefault(node, [-1] * 6)[names.index(name)] = i
        out = np.array(list(nodes.values()), dtype=np.intp)
        return out if np.any(out[:, 4:] >= 0) else out[:, :4]

    def _check_layout(self, what: str) -> None:
        if not self._regular():
            raise ValueError(
                f"{what} need (x, y, alpha, beta) at every node; this ROSS model has nodes "
                "with only x and y (point masses): use its matrices directly"
            )

    def plot_mode(self, speed: float, j: int, **kwargs: Any) -> Any:
        """:meth:`Rotor.plot_mode <duhamel.rotor.Rotor.plot_mode>` (4 dofs at every node)."""
        self._check_layout("mode plots")
        return super().plot_mode(speed, j, **kwargs)

    def _structure_stiffness(self) -> NDArray[np.float64]:
        """ROSS's stiffness without its bearings and seals (``K0``, else ``K(0)`` minus each
        bearing element's ``K(0)`` at its dofs), lateral block."""
        src = self.source
        K0 = getattr(src, "K0", None)
        if K0 is None:
            K0 = np.array(src.K(0.0), dtype=float)
            for b in getattr(src, "bearing_elements", ()):
                idx = list(b.dof_global_index.values())
                K0[np.ix_(idx, idx)] -= np.asarray(b.K(0.0), dtype=float)
        return np.asarray(K0, dtype=float)[self._blocks[0]]

    def critical_speed_map(
        self,
        stiffnesses: ArrayLike,
        *,
        n_modes: int = 4,
        gyroscopic: bool = True,
        speeds: ArrayLike | None = None,
    ) -> CriticalSpeedMap:
        """:meth:`Rotor.critical_speed_map <duhamel.rotor.Rotor.critical_speed_map>` of the
        ROSS model: its bearings (not its seals, as ROSS's ``run_ucs``) replaced by an
        isotropic spring of each of `stiffnesses` on their node's x and y, the shaft and
        disks as ROSS assembles them (``K0``, ``M``, ``G``), the bearings' ``kxx`` and ``kyy``
        curves from ROSS's interpolants (end values held beyond their frequencies).

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import from_ross
        >>> class Brg:
        ...     def __init__(self, n): self.n, self.frequency = n, None
        ...     kxx_interpolated = kyy_interpolated = staticmethod(lambda w: 1e6 + 0 * w)
        ...     kxy_interpolated = kyx_interpolated = staticmethod(lambda w: 0 * w)
        >>> class Toy:                       # a rigid disk (2 kg) on one bearing
        ...     elements = bearing_elements = [Brg(0)]
        ...     dof_global_index = {"x_0": 0, "y_0": 1, "alpha_0": 2, "beta_0": 3}
        ...     K0 = np.diag([0.0, 0.0, 1e6, 1e6])
        ...     def M(self, f=None): return np.diag([2.0, 2.0, 0.1, 0.1])
        ...     def K(self, f): return self.K0 + np.diag([1e6, 1e6, 0, 0])
        ...     def C(self, f): return np.zeros((4, 4))
        ...     def G(self): return np.zeros((4, 4))
        >>> Toy.elements[0].dof_global_index = Toy.dof_global_index
        >>> rotor = from_ross(Toy(), 0.0).rotor
        >>> ucs = rotor.critical_speed_map([2e4, 8e4], n_modes=1, gyroscopic=False,
        ...                                speeds=np.linspace(0.0, 1000.0, 101))
        >>> ucs.critical_speeds[:, 0].round(6).tolist()   # sqrt(k / 2 kg)
        [100.0, 200.0]
        >>> round(ucs.intersections[0].speed, 6)     # 1e6 N/m: sqrt(1e6 / 2)
        707.106781
        """
        from duhamel.rotor.critical_map import critical_speed_map

        if self.source is None:
            raise ValueError("a critical speed map needs the ROSS model (its bearings)")
        seal = _seal_class(self.source)
        link_nodes = set(getattr(self.source, "link_nodes", ()) or ())
        bearings = [
            b
            for b in getattr(self.source, "bearing_elements", ())
            if not (seal is not None and isinstance(b, seal)) and int(b.n) not in link_nodes
        ]
        if not bearings:
            raise ValueError("the ROSS model has no bearings: a critical speed map needs supports")
        for b in bearings:
            if getattr(b, "n_link", None) is not None:
                raise ValueError(
                    f"the ROSS bearing at node {b.n} is linked to node {b.n_link}: the map "
                    "takes only bearings between a shaft node and the ground"
                )
        self._check_layout("critical speed maps")
        M, _, _, G = self.matrices(0.0)
        supports = [(self.dof(int(b.n), "x"), self.dof(int(b.n), "y")) for b in bearings]
        lengths = [float(s.L) for s in self.shafts if hasattr(s, "L")]
        return critical_speed_map(
            M, self._structure_stiffness(), G, supports, [RossBearingCurve(b) for b in bearings],
            stiffnesses, n_modes=n_modes, gyroscopic=gyroscopic, speeds=speeds,
            length_scale=float(np.mean(lengths)) if lengths else 1.0,
        )  # fmt: skip

    def __repr__(self) -> str:
        return f"RossRotor(n_dof={self.n_dof}, source={type(self.source).__name__})"


def _seal_class(source: Any) -> Any:
    """ROSS's ``SealElement`` class when ROSS is imported (seals are not supports)."""
    import sys

    ross = sys.modules.get("ross")
    return getattr(ross, "SealElement", None) if ross is not None else None
