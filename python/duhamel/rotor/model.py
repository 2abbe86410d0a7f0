"""The rotor model: assembly, the duhamel System at a speed, complex modes, Campbell diagram.

Degrees of freedom: 4 per node, node ``i`` owning ``4 i + (0, 1, 2, 3)`` =
``(x, y, theta_x, theta_y)``; the shaft axis is z, nodes are numbered along it, and the
rotations are right-handed about the fixed x and y axes (so ``theta_y = dx/dz`` and
``theta_x = -dy/dz`` in pure bending). The shaft spins about +z at ``speed`` (rad/s); forward
whirl is an orbit in the sense of the spin, from +x towards +y. This is the convention of
Friswell, Penny, Garvey and Lees, *Dynamics of Rotating Machines* (2010), chapter 5.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from duhamel._validate import as_float_array, finite_float
from duhamel.elements import Element, LinearCoupling
from duhamel.loads import Load
from duhamel.rotor._speed import constant_speed, speed_or_law
from duhamel.rotor.components import Bearing, Disk
from duhamel.rotor.loads import Gravity, RotorLoad
from duhamel.rotor.shaft import Shaft
from duhamel.speed import SpeedLaw
from duhamel.system import System

__all__ = ["DIRECTIONS", "Campbell", "Modes", "Rotor", "RotorMatrices"]

#: Position of each direction within a node's four dofs.
DIRECTIONS = {"x": 0, "y": 1, "theta_x": 2, "theta_y": 3}
#: Eigenvalues with ``Im(lambda) <= ZERO_FREQUENCY_RTOL * max|lambda|`` are not oscillatory:
#: rigid-body modes (whose defective zero eigenvalues come out of the eigensolver as pairs of
#: size about ``sqrt(eps) max|lambda|``) and overdamped modes.
ZERO_FREQUENCY_RTOL = 1e-6
#: Orbit sense: a node counts when its amplitude is at least this fraction of the largest
#: node's, and its signed orbit area at least ``PLANAR_RTOL`` times its amplitude.
NODE_RTOL = 1e-4
PLANAR_RTOL = 1e-6
#: Eigenvalues within this relative distance form a cluster (a degenerate pair).
CLUSTER_RTOL = 1e-8
#: Campbell mode tracking: weight of the relative eigenvalue distance added to ``1 - MAC`` in
#: the assignment cost, so that it only breaks ties between equally similar shapes.
TRACK_TIE_WEIGHT = 1e-6


class RotorMatrices(NamedTuple):
    """The rotor's matrices: ``M x'' + (C + speed G) x' + K x = f``.

    ``K`` includes the full bearing stiffness (cross-coupled terms too), ``C`` the structural
    damping (Rayleigh or modal) and the full bearing damping; ``G`` is the gyroscopic matrix
    per unit speed (skew-symmetric).
    """

    M: NDArray[np.float64]
    K: NDArray[np.float64]
    C: NDArray[np.float64]
    G: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Modes:
    """Complex (damped) modes of the rotor at one speed, ascending in frequency.

    Each mode is a solution ``x(t) = Re(shape e^{lambda t})`` of the free rotor with
    ``Im(lambda) > 0``.

    Attributes
    ----------
    speed : float
        Spin speed (rad/s).
    eigenvalues : ndarray of complex, shape (n_modes,)
        ``lambda = -zeta omega_n + i omega_d``.
    shapes : ndarray of complex, shape (n_dof, n_modes)
        Mode shapes, scaled so that the translation of largest magnitude is 1 (real).
    whirl : tuple of str
        ``"forward"`` (every moving node orbits in the sense of the spin: from +x towards +y
        for ``speed >= 0``), ``"backward"``, ``"mixed"`` (nodes disagree) or ``"planar"``
        (straight-line orbits). Within a pair of equal eigenvalues (an axisymmetric rotor,
        or any rotor at zero speed with isotropic bearings) the shapes are chosen as the
        backward and the forward circular orbits.
    length_scale : float
        Length (m) that weights the rotations against the translations in :meth:`mac` and in
        the whirl (the rotor's mean element length; 1 by default).
    """

    speed: float
    eigenvalues: NDArray[np.complex128]
    shapes: NDArray[np.complex128]
    whirl: tuple[str, ...]
    length_scale: float = 1.0

    @property
    def n_modes(self) -> int:
        """Number of modes."""
        return int(self.eigenvalues.size)

    @property
    def frequencies(self) -> NDArray[np.float64]:
        """Damped natural frequencies ``Im(lambda)`` (rad/s)."""
        return self.eigenvalues.imag.copy()

    @property
    def damping_ratios(self) -> NDArray[np.float64]:
        """``-Re(lambda) / |lambda|`` (negative: unstable)."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def log_dec(self) -> NDArray[np.float64]:
        """Logarithmic decrement ``-2 pi Re(lambda) / Im(lambda)`` (negative: unstable)."""
        return -2.0 * np.pi * self.eigenvalues.real / self.eigenvalues.imag

    def mac(self, other: Modes) -> NDArray[np.float64]:
        """Modal assurance criterion between these mode shapes and `other`'s.

        ``MAC[i, j] = |u_i^H v_j|^2 / (|u_i|^2 |v_j|^2)`` on the complex displacement shapes
        (``u_i = shapes[:, i]``, ``v_j = other.shapes[:, j]``), with the rotations multiplied
        by :attr:`length_scale` so that every entry is a length. 1 for proportional shapes, 0
        for orthogonal ones (a forward and a backward circular orbit of an isotropic rotor).

        Parameters
        ----------
        other : Modes
            Modes of a model with the same degrees of freedom (e.g. at another speed).

        Returns
        -------
        ndarray, shape (n_modes, other.n_modes)

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.3, 0.16)],
        ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
        >>> a, b = rotor.modes(100.0, n=2), rotor.modes(150.0, n=2)
        >>> a.whirl, np.round(a.mac(b), 6).tolist()
        (('backward', 'forward'), [[1.0, 0.0], [0.0, 1.0]])
        """
        if not isinstance(other, Modes):
            raise TypeError(f"`other` must be Modes, got {type(other).__name__}")
        if other.shapes.shape[0] != self.shapes.shape[0]:
            raise ValueError(
                f"`other` has {other.shapes.shape[0]} degrees of freedom, these modes "
                f"{self.shapes.shape[0]}"
            )
        return _mac(self.shapes, other.shapes, self.length_scale)


@dataclass(frozen=True, eq=False)
class Campbell:
    """Damped natural frequencies against speed, from :meth:`Rotor.campbell`.

    Tracked (``tracked=True``): column ``j`` follows one branch (one physical mode) through
    crossings. Untracked: column ``j`` is the ``j``-th lowest frequency at each speed. Rows are
    in the order of `speeds` as given. Missing entries (fewer oscillatory modes at a speed, or,
    tracked, a branch that is not among the lowest ``n_modes`` there) are NaN, whirl ``""``.

    Attributes
    ----------
    speeds : ndarray, shape (n_speeds,)
        rad/s.
    frequencies, damping_ratios : ndarray, shape (n_speeds, n_columns)
        rad/s, and ``-Re(lambda)/|lambda|``.
    whirl : ndarray of str, shape (n_speeds, n_columns)
        As :attr:`Modes.whirl`.
    mac : ndarray, shape (n_speeds, n_columns), optional
        :meth:`Modes.mac` between the shape in each cell and the shape of the same column at
        the next lower speed of `speeds` (tracked: the matched pair); NaN at the lowest speed
        and where either is missing. Near 1 along a well-resolved branch; a low value flags a
        crossing or veering that the speed grid does not resolve (refine it there).
    tracked : bool
        Whether the columns are tracked branches.
    """

    speeds: NDArray[np.float64]
    frequencies: NDArray[np.float64]
    damping_ratios: NDArray[np.float64]
    whirl: NDArray[np.str_]
    mac: NDArray[np.float64] | None = None
    tracked: bool = False

    def plot(self, **kwargs: Any) -> Any:
        """Plot with :func:`duhamel.rotor.plot_campbell` (same keywords); returns the Axes."""
        from duhamel.rotor.plot import plot_campbell

        return plot_campbell(self, **kwargs)


def _sequence(items: Any, kind: type, name: str) -> tuple[Any, ...]:
    if isinstance(items, kind):
        items = [items]
    out = tuple(items)
    for i, item in enumerate(out):
        if not isinstance(item, kind):
            raise TypeError(
                f"`{name}[{i}]` must be a duhamel.rotor.{kind.__name__}, got {type(item).__name__}"
            )
    return out


def _nonzero(a: NDArray[np.float64]) -> bool:
    return bool(np.any(a != 0.0))


class Rotor:
    """A finite-element rotor: Timoshenko shaft elements, rigid disks and bearings.

    Parameters
    ----------
    shafts : sequence of Shaft
        In order along the axis; shaft ``i`` joins nodes ``i`` and ``i + 1``, so the rotor
        has ``len(shafts) + 1`` nodes (one node when there is no shaft).
    disks : sequence of Disk
        Rigid disks at nodes (several at a node add up).
    bearings : sequence of Bearing
        Bearings at nodes (several at a node add up), with constant coefficients or
        coefficients tabulated against the spin speed (``Bearing(..., speeds=...)``), which
        every method that takes a speed evaluates there.
    zeta : float or array_like, optional
        Keyword only. Modal damping ratio of every mode of the symmetric background
        ``(K_sym, M)`` (one value, or one per mode: ``n_dof`` values), as
        ``duhamel.System(zeta=...)``.
    rayleigh : (float, float), optional
        Keyword only. Structural damping ``alpha M + beta K_sym``.

    At most one of `zeta` and `rayleigh`. Bearing damping comes on top of either.
    ``K_sym`` is the shaft stiffness plus the symmetric part of the bearing stiffness.

    Examples
    --------
    A 1.5 m steel shaft on two bearings with a disk in the middle:

    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
    >>> shafts = [Shaft(0.25, 0.05, material=STEEL) for _ in range(6)]
    >>> disk = Disk.from_geometry(3, width=0.07, outer_diameter=0.28, inner_diameter=0.05,
    ...                           material=STEEL)
    >>> bearings = [Bearing(0, kxx=1e6, kyy=1e6), Bearing(6, kxx=1e6, kyy=1e6)]
    >>> rotor = Rotor(shafts, [disk], bearings)
    >>> rotor
    Rotor(nodes=7, n_dof=28, shafts=6, disks=1, bearings=2)
    >>> np.round(rotor.natural_frequencies(speed=0.0)[:4] / (2 * np.pi), 3).tolist()
    [18.523, 18.523, 73.891, 73.891]
    >>> modes = rotor.modes(speed=4000 * np.pi / 30)   # 4000 rpm: the pairs split
    >>> np.round(modes.frequencies[:4] / (2 * np.pi), 3).tolist(), modes.whirl[:4]
    ([18.518, 18.528, 69.607, 77.783], ('backward', 'forward', 'backward', 'forward'))
    """

    def __init__(
        self,
        shafts: Sequence[Shaft] | Shaft,
        disks: Sequence[Disk] | Disk = (),
        bearings: Sequence[Bearing] | Bearing = (),
        *,
        zeta: float | ArrayLike | None = None,
        rayleigh: tuple[float, float] | None = None,
    ) -> None:
        self.shafts: tuple[Shaft, ...] = _sequence(shafts, Shaft, "shafts")
        self.disks: tuple[Disk, ...] = _sequence(disks, Disk, "disks")
        self.bearings: tuple[Bearing, ...] = _sequence(bearings, Bearing, "bearings")
        n_nodes = len(self.shafts) + 1
        for name, items in (("disks", self.disks), ("bearings", self.bearings)):
            for i, item in enumerate(items):
                if item.node >= n_nodes:
                    raise ValueError(
                        f"`{name}[{i}]` is at node {item.node}, but the rotor has nodes "
                        f"0..{n_nodes - 1} ({len(self.shafts)} shafts)"
                    )
        if zeta is not None and rayleigh is not None:
            raise ValueError("give at most one of `zeta` and `rayleigh`")
        self._zeta: float | NDArray[np.float64] | None = None
        self._rayleigh: tuple[float, float] | None = None
        if zeta is not None:
            if np.ndim(zeta) == 0:
                self._zeta = finite_float(zeta, "zeta")
            else:
                z = as_float_array(zeta, "zeta", ndim=1)
                if z.size != self.n_dof:
                    raise ValueError(
                        f"`zeta` must be one value or one per mode (n_dof = {self.n_dof}), "
                        f"got {z.size}"
                    )
                self._zeta = z
        if rayleigh is not None:
            a, b = as_float_array(rayleigh, "rayleigh", shape=(2,)).tolist()
            self._rayleigh = (a, b)

    # ------------------------------------------------------------------ layout
    @property
    def n_nodes(self) -> int:
        """Number of nodes, ``len(shafts) + 1``."""
        return len(self.shafts) + 1

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom, ``4 n_nodes``."""
        return 4 * self.n_nodes

    @property
    def nodes_z(self) -> NDArray[np.float64]:
        """Axial positions of the nodes (m), node 0 at ``z = 0``."""
        return np.concatenate([[0.0], np.cumsum([s.L for s in self.shafts])])

    @property
    def mass(self) -> float:
        """Total mass (kg): shafts and disks."""
        return float(sum(s.mass for s in self.shafts) + sum(d.mass for d in self.disks))

    def dof(self, node: int, direction: str | int) -> int:
        """Global index of a node's degree of freedom.

        Parameters
        ----------
        node : int
            Node number, ``0 <= node < n_nodes``.
        direction : {"x", "y", "theta_x", "theta_y"} or int 0..3

        Examples
        --------
        >>> from duhamel.rotor import STEEL, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.5, 0.05, material=STEEL)] * 4)
        >>> rotor.dof(3, "x"), rotor.dof(3, "y"), rotor.dof(3, "theta_y")
        (12, 13, 15)
        """
        if isinstance(node, bool) or not isinstance(node, int | np.integer):
            raise TypeError(f"`node` must be an integer, got {type(node).__name__}")
        if not 0 <= node < self.n_nodes:
            raise ValueError(f"`node` must be in [0, {self.n_nodes - 1}], got {node}")
        if isinstance(direction, str):
            if direction not in DIRECTIONS:
                raise ValueError(
                    f"`direction` must be one of {list(DIRECTIONS)}, got {direction!r}"
                )
            k = DIRECTIONS[direction]
        elif isinstance(direction, int | np.integer) and 0 <= direction < 4:
            k = int(direction)
        else:
            raise ValueError(f"`direction` must be a name or 0..3, got {direction!r}")
        return 4 * int(node) + k

    def __repr__(self) -> str:
        return (
            f"Rotor(nodes={self.n_nodes}, n_dof={self.n_dof}, shafts={len(self.shafts)}, "
            f"disks={len(self.disks)}, bearings={len(self.bearings)})"
        )

    # ------------------------------------------------------------------ assembly
    @cached_property
    def _assembled(self) -> dict[str, NDArray[np.float64]]:
        n = self.n_dof
        M, K, G = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
        for i, shaft in enumerate(self.shafts):
            me, ke, ge = shaft.matrices()
            s = slice(4 * i, 4 * i + 8)
            M[s, s] += me
            K[s, s] += ke
            G[s, s] += ge
        for disk in self.disks:
            md, gd = disk.matrices()
            s = slice(4 * disk.node, 4 * disk.node + 4)
            M[s, s] += md
            G[s, s] += gd
        # the constant-coefficient bearings, once; speed-dependent ones per speed
        Kb, Cb = np.zeros((n, n)), np.zeros((n, n))
        for b in self.bearings:
            if not b.is_speed_dependent:
                ix = [4 * b.node, 4 * b.node + 1]
                Kb[np.ix_(ix, ix)] += b.stiffness
                Cb[np.ix_(ix, ix)] += b.damping
        out = {"M": M, "K_shaft": K, "G": G, "K_bearing": Kb, "C_bearing": Cb}
        for a in out.values():
            a.setflags(write=False)
        return out

    @cached_property
    def _speed_bearings(self) -> tuple[Bearing, ...]:
        return tuple(b for b in self.bearings if b.is_speed_dependent)

    @property
    def has_speed_dependent_bearings(self) -> bool:
        """Whether any bearing has coefficients tabulated against the spin speed."""
        return bool(self._speed_bearings)

    def _bearing_matrices(self, speed: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Full bearing stiffness and damping ``(K_b, C_b)`` at `speed` (the cached
        constant part when no bearing depends on the speed)."""
        a = self._assembled
        if not self._speed_bearings:
            return a["K_bearing"], a["C_bearing"]
        kb, cb = a["K_bearing"].copy(), a["C_bearing"].copy()
        for b in self._speed_bearings:
            ix = np.ix_([4 * b.node, 4 * b.node + 1], [4 * b.node, 4 * b.node + 1])
            kb[ix] += b.stiffness_at(speed)
            cb[ix] += b.damping_at(speed)
        return kb, cb

    def _massless_nodes(self) -> list[int]:
        diag = np.diag(self._assembled["M"]).reshape(self.n_nodes, 4)
        return [int(i) for i in np.flatnonzero(np.any(diag <= 0.0, axis=1))]

    def _k_sym(self, kb: NDArray[np.float64]) -> NDArray[np.float64]:
        return self._assembled["K_shaft"] + (kb + kb.T) / 2.0

    def structural_damping(self, speed: float = 0.0) -> NDArray[np.float64]:
        """The structural damping matrix (without the bearings): ``alpha M + beta K_sym``,
        or ``M Phi diag(2 zeta omega) Phi^T M`` from the mass-normalised undamped modes of
        ``(K_sym, M)`` (rigid-body modes get none), or zero.

        ``K_sym`` (shaft + symmetric part of the bearing stiffness) is taken at spin speed
        `speed` (rad/s), which matters only with speed-dependent bearings."""
        w = finite_float(speed, "speed")
        if not self._speed_bearings:
            return self._structural_damping.copy()
        return self._structural(self._k_sym(self._bearing_matrices(w)[0]))

    @cached_property
    def _structural_damping(self) -> NDArray[np.float64]:
        return self._structural(self._k_sym(self._assembled["K_bearing"]))

    def _structural(self, k_sym: NDArray[np.float64]) -> NDArray[np.float64]:
        M = self._assembled["M"]
        if self._rayleigh is not None:
            a, b = self._rayleigh
            return a * M + b * k_sym
        if self._zeta is not None:
            if self._massless_nodes():
                raise ValueError(
                    "modal damping `zeta` needs mass at every node; the rotor has massless "
                    f"nodes {self._massless_nodes()} (use `rayleigh` or give them mass)"
                )
            lam, phi = scipy.linalg.eigh(k_sym, M)
            scale = max(float(np.max(np.abs(lam))), 1.0)
            omega = np.sqrt(np.where(lam > 1e-12 * scale, lam, 0.0))
            mphi = M @ phi
            return (mphi * (2.0 * np.asarray(self._zeta) * omega)) @ mphi.T
        return np.zeros_like(M)

    def matrices(self, speed: float = 0.0) -> RotorMatrices:
        """Global matrices ``(M, K, C, G)`` of ``M x'' + (C + speed G) x' + K x = f``.

        Parameters
        ----------
        speed : float
            Spin speed (rad/s) at which speed-dependent bearing coefficients are evaluated
            (and, through ``K_sym``, Rayleigh or modal structural damping); with
            constant-coefficient bearings ``(M, K, C, G)`` do not depend on it (as ROSS's
            ``M(), K(speed), C(speed), G()``).

        Returns
        -------
        RotorMatrices
            ``M``, ``K`` (shaft + full bearing stiffness), ``C`` (structural + full bearing
            damping) and ``G`` (per unit speed), dense ``(n_dof, n_dof)`` arrays.

        Examples
        --------
        >>> from duhamel.rotor import STEEL, Bearing, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.5, 0.05, material=STEEL)],
        ...               bearings=[Bearing(0, 1e7, 1e7, kxy=1e5, kyx=-1e5)])
        >>> M, K, C, G = rotor.matrices()
        >>> float(K[0, 1]), float(K[1, 0]), bool((G == -G.T).all())
        (100000.0, -100000.0, True)
        """
        w = finite_float(speed, "speed")
        a = self._assembled
        kb, cb = self._bearing_matrices(w)
        K = a["K_shaft"] + kb
        C = self.structural_damping(w) + cb
        return RotorMatrices(a["M"].copy(), K, C, a["G"].copy())

    def static_deflection(self, g: float = 9.81, *, speed: float = 0.0) -> NDArray[np.float64]:
        """Linear static deflection under the rotor's own weight (along ``-y``), ``K^-1 f_g``,
        with the full linear stiffness (nonlinear bearing parts left out) at spin speed
        `speed` (rad/s, keyword only; it matters only with speed-dependent bearings).

        Examples
        --------
        >>> from duhamel.rotor import STEEL, Bearing, Rotor, Shaft
        >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)],
        ...               bearings=[Bearing(0, 1e6, 1e6), Bearing(1, 1e6, 1e6)])
        >>> round(float(rotor.static_deflection()[1]) * 1e6, 3)   # at a bearing: -m g / (2 k)
        -75.218

        Bearings twice as stiff at 1000 rad/s as at rest:

        >>> fluid = [Bearing(n, [1e6, 2e6], [1e6, 2e6], speeds=[0, 1000]) for n in (0, 1)]
        >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)], bearings=fluid)
        >>> round(float(rotor.static_deflection(speed=1000.0)[1]) * 1e6, 3)
        -37.609
        """
        K = self.matrices(constant_speed(speed)).K
        f = Gravity(g=g).vector(self)
        try:
            return np.asarray(scipy.linalg.solve(K, f), dtype=np.float64)
        except (np.linalg.LinAlgError, scipy.linalg.LinAlgError) as exc:
            raise ValueError(
                "the rotor's stiffness matrix is singular (is it supported by bearings?)"
            ) from exc

    # ------------------------------------------------------------------ time integration
    def system(
        self,
        speed: Any = 0.0,
        loads: Iterable[RotorLoad | Load] = (),
        *,
        sparse: bool = False,
    ) -> System:
        """The rotor at `speed` (constant, or a run-up) as a :class:`duhamel.System`.

        * Background (integrated exactly by :class:`duhamel.Semianalytic`): ``M``,
          ``K_sym`` = shaft stiffness + symmetric part of the bearing stiffness, and the
          damping: ``zeta``/``rayleigh`` as given, or, when the bearings have (symmetric)
          damping, ``C = structural + symmetric bearing damping`` as a matrix (its modal
          diagonal stays exact, the rest is a pseudo-force, see ``duhamel.System``).
        * The gyroscopic terms: ``LinearCoupling(C=speed G)`` at a constant speed (omitted
          at zero speed), ``LinearCoupling(C=G, scale=law)`` along a varying speed law
          (``duhamel.speed.LinearRunUp``: the force ``omega(t) G x'``).
        * ``LinearCoupling(K=skew(K_b), C=skew(C_b))``: the skew-symmetric parts of the
          bearing stiffness and damping (omitted when zero).
        * The bearings' nonlinear parts: ``Cubic`` on x and y for a cubic law, ``Contact``
          for a rub.
        * `loads`: rotor loads (:class:`Unbalance`, :class:`Gravity`, :class:`SuddenForce`;
          an ``Unbalance`` without its own speed takes `speed`, a run-up included) and plain
          :mod:`duhamel.loads`.

        Parameters
        ----------
        speed : float or speed law
            Spin speed (rad/s), or a :mod:`duhamel.speed` law (``ConstantSpeed``, or
            ``LinearRunUp`` for a run-up or run-down; the bearing coefficients stay
            constant, so a varying law needs constant-coefficient bearings). Speed-dependent
            bearings are evaluated at a constant speed.
        loads : iterable
            Loads to add.
        sparse : bool
            Keyword only. Store ``M``, ``K_sym`` and the couplings as ``scipy.sparse`` CSR
            (large models; ``duhamel.Semianalytic(modes=n)`` then uses a sparse
            eigensolver and the direct integrators sparse factorisations).

        Returns
        -------
        System

        Raises
        ------
        ValueError
            If a node has no mass (``rho = 0`` shafts without a disk there), an
            ``Unbalance`` has a speed other than `speed`, or `speed` varies (a run-up) and a
            bearing has speed-dependent coefficients: the engine's couplings are constant
            matrices times a scalar law and cannot follow coefficients that change with the
            speed.
        TypeError
            If `speed` is neither a number nor a speed law.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, Unbalance, rpm
        >>> rotor = Rotor([Shaft(0.3, 0.05, material=STEEL)] * 4,
        ...               [Disk(2, 20.0, 0.2, 0.1)],
        ...               [Bearing(0, 1e7, 1e7, kxy=1e5, kyx=-1e5, cxx=500.0, cyy=500.0),
        ...                Bearing(4, 1e7, 1e7, kxy=1e5, kyx=-1e5, cxx=500.0, cyy=500.0)],
        ...               rayleigh=(0.0, 1e-5))
        >>> system = rotor.system(rpm(3000), [Unbalance(2, m_e=1e-4)])
        >>> system
        System(n_dof=20, damping='matrix', loads=1, elements=2)
        >>> sol = duhamel.solve(system, duhamel.Semianalytic(modes=8), t_end=0.1, dt=1e-4)
        >>> sol.x.shape
        (1001, 20)

        A run-up from rest to 3000 rpm in 0.1 s, then at constant speed:

        >>> run_up = duhamel.speed.LinearRunUp(omega0=0.0, omega1=rpm(3000), t1=0.1)
        >>> system = rotor.system(run_up, [Unbalance(2, m_e=1e-4)])
        >>> system.elements[0].scale is run_up
        True
        >>> sol = duhamel.solve(system, duhamel.Newmark(), t_end=0.15, dt=1e-4)
        """
        w = speed_or_law(speed)  # a float, or a varying SpeedLaw
        if isinstance(w, SpeedLaw) and self._speed_bearings:
            nodes = sorted({b.node for b in self._speed_bearings})
            raise ValueError(
                f"`speed` is the varying speed law {w!r}, but the bearings at nodes {nodes} "
                "have speed-dependent coefficients: the transient engine applies constant "
                "bearing matrices (its couplings are constant matrices times a scalar speed "
                "law), so it cannot follow coefficients that change with the speed. Use a "
                "constant speed, or constant-coefficient bearings (e.g. from "
                "Bearing.stiffness_at / damping_at at a representative speed)"
            )
        w_const = w if isinstance(w, float) else 0.0  # where the bearings are evaluated
        massless = self._massless_nodes()
        if massless:
            raise ValueError(
                f"nodes {massless} have no mass (shafts with rho = 0 and no disk there); a "
                "time integration needs mass at every degree of freedom"
            )
        a = self._assembled
        kb, cb = self._bearing_matrices(w_const)
        M, k_sym = a["M"], self._k_sym(kb)
        k_skew, c_skew = (kb - kb.T) / 2.0, (cb - cb.T) / 2.0
        c_sym = (cb + cb.T) / 2.0
        conv = sp.csr_array if sparse else (lambda m: m)
        if _nonzero(c_sym):
            system = System(conv(M), conv(k_sym), conv(self.structural_damping(w_const) + c_sym))
        elif self._rayleigh is not None:
            system = System(conv(M), conv(k_sym), rayleigh=self._rayleigh)
        elif self._zeta is not None:
            system = System(conv(M), conv(k_sym), zeta=self._zeta)
        else:
            system = System(conv(M), conv(k_sym))
        if isinstance(w, SpeedLaw):  # a run-up: the engine scales G by omega(t)
            if _nonzero(a["G"]):
                system.add(LinearCoupling(C=conv(a["G"]), scale=w))
        elif _nonzero(w * a["G"]):
            system.add(LinearCoupling(C=conv(w * a["G"])))
        if _nonzero(k_skew) or _nonzero(c_skew):
            system.add(
                LinearCoupling(
                    K=conv(k_skew) if _nonzero(k_skew) else None,
                    C=conv(c_skew) if _nonzero(c_skew) else None,
                )
            )
        for element in self.nonlinear_elements(w_const):
            system.add(element)
        for load in loads:
            if isinstance(load, RotorLoad):
                for part in load.loads(self, w):
                    system.add_load(part)
            elif isinstance(load, Load):
                system.add_load(load)
            else:
                raise TypeError(
                    "`loads` must contain duhamel.rotor loads (Unbalance, Gravity, "
                    f"SuddenForce) or duhamel.loads loads, got {type(load).__name__}"
                )
        return system

    def nonlinear_elements(self, speed: float = 0.0) -> list[Element]:
        """The bearings' nonlinear parts as :mod:`duhamel.elements` (global dofs).

        A cubic law without its own ``x_stat`` uses the magnitude of the bearing's vertical
        deflection in :meth:`static_deflection` (``g = 9.81``). `speed` (rad/s) is where
        speed-dependent bearings are evaluated (the static deflection, and ``kxx``, ``kyy`` of
        a cubic law); it does not matter otherwise.
        """
        w = constant_speed(speed)
        out: list[Element] = []
        static: NDArray[np.float64] | None = None
        for b in self.bearings:
            dx, dy = self.dof(b.node, "x"), self.dof(b.node, "y")
            x_stat = b.x_stat
            if b.beta != 0.0 and x_stat is None:
                if static is None:
                    static = self.static_deflection(speed=w)
                x_stat = abs(float(static[dy]))
                if x_stat == 0.0:
                    raise ValueError(
                        f"the bearing at node {b.node} does not deflect under the weight; "
                        "give its cubic law an `x_stat`"
                    )
            out.extend(b.elements(dx, dy, x_stat, speed=w))
        return out

    # ------------------------------------------------------------------ eigenvalues
    def modes(self, speed: float = 0.0, n: int | None = None) -> Modes:
        """Complex modes at constant `speed` from the first-order eigenproblem.

        ``(lambda^2 M + lambda (C + speed G) + K) u = 0`` with the full ``K`` and ``C`` (all
        bearing terms), linearised as ``[[0, s I], [-K/s, -(C + speed G)]] z = lambda
        [[I, 0], [0, M]] z`` (``s`` a frequency scale) and solved by the QZ algorithm, so
        that massless degrees of freedom (``rho = 0`` shafts, Jeffcott models) are allowed:
        they give infinite eigenvalues, which are dropped. Only oscillatory modes are kept
        (``Im(lambda) > 1e-6 max|lambda|``: rigid-body and overdamped modes are left out).

        Parameters
        ----------
        speed : float
            Spin speed (rad/s); speed-dependent bearings take their coefficients there.
        n : int, optional
            Keep the lowest `n` modes (default: all oscillatory ones).

        Returns
        -------
        Modes
        """
        w = constant_speed(speed)
        M, K, C, G = self.matrices(w)
        lam, shapes = _complex_modes(M, C + w * G, K)
        if n is not None:
            if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
                raise ValueError(f"`n` must be a positive integer, got {n!r}")
            lam, shapes = lam[:n], shapes[:, :n]
        lengths = [s.L for s in self.shafts]
        ell = float(np.mean(lengths)) if lengths else 1.0
        shapes = _circular_pairs(lam, shapes, ell)
        whirl = tuple(_whirl(shapes[:, j].reshape(self.n_nodes, 4), ell) for j in range(lam.size))
        if w < 0.0:  # spinning about -z: the whirl sense relative to the spin flips
            flip = {"forward": "backward", "backward": "forward"}
            whirl = tuple(flip.get(k, k) for k in whirl)
        return Modes(speed=w, eigenvalues=lam, shapes=shapes, whirl=whirl, length_scale=ell)

    def natural_frequencies(self, speed: float = 0.0, n: int | None = None) -> NDArray[np.float64]:
        """Damped natural frequencies (rad/s, ascending) at constant `speed`:
        ``Im(lambda)`` of :meth:`modes`."""
        return self.modes(speed, n).frequencies

    def campbell(
        self, speeds: ArrayLike, n_modes: int | None = None, *, track: bool = True
    ) -> Campbell:
        """Damped natural frequencies at each of `speeds` (rad/s), modes tracked by shape.

        With ``track=True`` (the default) the modes at each speed are matched to those at the
        next lower speed by their shapes: the cost ``1 - MAC`` (:meth:`Modes.mac`: rotations
        weighted by the mean element length) of every pair is minimised over one-to-one
        assignments (``scipy.optimize.linear_sum_assignment``; the relative eigenvalue
        distance, weighted ``1e-6``, only breaks ties). Column ``j`` then follows one branch
        through crossings: where a forward whirl branch crosses a backward one, the columns
        do not swap. All oscillatory modes are tracked; `n_modes` then selects what is shown.
        With ``track=False``, column ``j`` is the ``j``-th lowest frequency at each speed.

        Parameters
        ----------
        speeds : array_like
            Spin speeds (rad/s), in any order: the tracking walks them in ascending order and
            the rows come back in the order given (repeated speeds are allowed). Across zero
            speed a branch keeps its orbit sense, so its whirl label (relative to the spin)
            changes from backward to forward there.
        n_modes : int, optional
            Show the lowest `n_modes` modes at each speed (default: all oscillatory modes).
            Untracked: ``n_modes`` columns. Tracked: one column per branch that is among the
            lowest ``n_modes`` at some speed, NaN where it is not (so a branch may enter or
            leave the window where it crosses the ``n_modes``-th mode, and there may be more
            than ``n_modes`` columns); every row shows the same frequencies as untracked.
        track : bool
            Keyword only. Track modes through crossings (default), or sort them by
            frequency at each speed (the behaviour before tracking existed).

        Returns
        -------
        Campbell
            Tracked columns are ordered by where their branch enters: first the branches at
            the lowest speed, ascending, then branches that appear (modes that become
            oscillatory, or enter the ``n_modes`` window) at higher speeds. A mode that stops
            being oscillatory ends its branch (NaN from there); ``Campbell.mac`` flags poorly
            resolved crossings.

        Examples
        --------
        A disk at mid-span: the backward whirl of the tilt mode falls through the forward
        whirl of the translational mode near 4000 rad/s.

        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
        >>> speeds = np.linspace(0.0, 5000.0, 26)
        >>> tracked = rotor.campbell(speeds, n_modes=4)
        >>> tracked.frequencies.shape
        (26, 4)
        >>> [np.unique(tracked.whirl[:, j]).tolist() for j in range(4)]
        [['backward'], ['forward'], ['backward'], ['forward']]
        >>> np.round(tracked.frequencies[-1], 1).tolist()    # at 5000 rad/s
        [263.9, 266.1, 216.1, 2167.8]
        >>> untracked = rotor.campbell(speeds, n_modes=4, track=False)
        >>> np.unique(untracked.whirl[1:, 1]).tolist()       # the second lowest: two branches
        ['backward', 'forward']
        >>> round(float(np.nanmin(tracked.mac)), 3)          # every matched pair
        0.993
        """
        ws = as_float_array(speeds, "speeds", ndim=1)
        if n_modes is not None and (
            isinstance(n_modes, bool) or not isinstance(n_modes, int | np.integer) or n_modes < 1
        ):
            raise ValueError(f"`n_modes` must be a positive integer, got {n_modes!r}")
        if not isinstance(track, bool | np.bool_):
            raise TypeError(f"`track` must be a bool, got {type(track).__name__}")
        order = np.argsort(ws, kind="stable")  # the path the tracking walks
        if track:
            return self._tracked_campbell(ws, order, n_modes)
        found = [self.modes(float(w), n_modes) for w in ws]
        m = max((f.n_modes for f in found), default=0) if n_modes is None else int(n_modes)
        freq = np.full((ws.size, m), np.nan)
        zeta = np.full((ws.size, m), np.nan)
        whirl = np.full((ws.size, m), "", dtype="<U8")
        mac = np.full((ws.size, m), np.nan)
        for i, f in enumerate(found):
            k = min(f.n_modes, m)
            freq[i, :k] = f.frequencies[:k]
            zeta[i, :k] = f.damping_ratios[:k]
            whirl[i, :k] = f.whirl[:k]
        for p in range(1, ws.size):
            prev, cur = found[order[p - 1]], found[order[p]]
            k = min(prev.n_modes, cur.n_modes, m)
            mac[order[p], :k] = _mac_columns(
                prev.shapes[:, :k], cur.shapes[:, :k], cur.length_scale
            )
        return Campbell(ws, freq, zeta, whirl, mac=mac, tracked=False)

    def _tracked_campbell(
        self, ws: NDArray[np.float64], order: NDArray[np.intp], n_modes: int | None
    ) -> Campbell:
        path = [self.modes(float(ws[i])) for i in order]
        # branch[p][k]: the branch of mode k at the p-th lowest speed; pair[p][k]: its MAC
        # with its predecessor on the branch (NaN for a branch that starts there)
        branch: list[NDArray[np.intp]] = []
        pair: list[NDArray[np.float64]] = []
        n_branches = 0
        for p, cur in enumerate(path):
            ids = np.full(cur.n_modes, -1, dtype=np.intp)
            macs = np.full(cur.n_modes, np.nan)
            if p > 0 and path[p - 1].n_modes and cur.n_modes:
                prev = path[p - 1]
                mac = prev.mac(cur)
                lp, lc = prev.eigenvalues[:, None], cur.eigenvalues[None, :]
                dist = np.abs(lp - lc) / np.maximum(np.abs(lp), np.abs(lc))
                rows, cols = linear_sum_assignment(1.0 - mac + TRACK_TIE_WEIGHT * dist)
                ids[cols] = branch[p - 1][rows]
                macs[cols] = mac[rows, cols]
            new = ids < 0  # modes without a predecessor start branches
            ids[new] = n_branches + np.arange(int(new.sum()))
            n_branches += int(new.sum())
            branch.append(ids)
            pair.append(macs)
        # the columns: branches among the lowest n_modes somewhere, in order of entry: by
        # speed, then frequency, equal frequencies (a degenerate pair) by the next speed's
        entry: dict[int, tuple[int, int, float]] = {}
        for p, (f, ids) in enumerate(zip(path, branch, strict=True)):
            freqs = f.frequencies
            cluster = np.concatenate(
                [[0], np.cumsum(np.diff(freqs) > CLUSTER_RTOL * np.abs(freqs[1:]))]
            )
            for k, b in enumerate(ids[:n_modes] if n_modes is not None else ids):
                if int(b) not in entry:
                    later = np.flatnonzero(branch[p + 1] == b) if p + 1 < len(path) else []
                    after = float(path[p + 1].frequencies[later[0]]) if len(later) else np.inf
                    entry[int(b)] = (p, int(cluster[k]), after)
        column = {b: j for j, b in enumerate(sorted(entry, key=entry.__getitem__))}
        m = len(column)
        freq = np.full((ws.size, m), np.nan)
        zeta = np.full((ws.size, m), np.nan)
        whirl = np.full((ws.size, m), "", dtype="<U8")
        mac = np.full((ws.size, m), np.nan)
        for p, (f, ids, macs) in enumerate(zip(path, branch, pair, strict=True)):
            k = f.n_modes if n_modes is None else min(f.n_modes, int(n_modes))
            row = order[p]
            cols = [column[int(b)] for b in ids[:k]]
            freq[row, cols] = f.frequencies[:k]
            zeta[row, cols] = f.damping_ratios[:k]
            whirl[row, cols] = f.whirl[:k]
            mac[row, cols] = macs[:k]
        return Campbell(ws, freq, zeta, whirl, mac=mac, tracked=True)

    def plot_campbell(
        self,
        speeds: ArrayLike,
        n_modes: int | None = None,
        *,
        track: bool = True,
        **kwargs: Any,
    ) -> Any:
        """:meth:`campbell` then :func:`duhamel.rotor.plot_campbell`; returns the Axes."""
        return self.campbell(speeds, n_modes, track=track).plot(**kwargs)


def _complex_modes(
    M: NDArray[np.float64], D: NDArray[np.float64], K: NDArray[np.float64]
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Oscillatory eigenpairs of ``lambda^2 M + lambda D + K``, ``Im(lambda) > 0``, ascending.

    Without damping and gyroscopic terms (``D = 0``, ``K`` symmetric, ``M`` positive
    definite) the eigenvalues are ``+-i omega`` with ``omega^2`` those of ``(K, M)``: solved by
    the symmetric eigensolver, exactly as the state-space problem but faster and to full
    accuracy. Otherwise the QZ algorithm on the scaled first-order pencil.
    """
    n = M.shape[0]
    if not np.any(D) and np.array_equal(K, K.T):
        try:
            lam2, vec = scipy.linalg.eigh(K, M, check_finite=False)
        except np.linalg.LinAlgError:  # singular M (massless dofs): the general path
            pass
        else:
            omega = np.sqrt(np.clip(lam2, 0.0, None))
            keep = omega > ZERO_FREQUENCY_RTOL * float(omega.max())
            return 1j * omega[keep], _normalise(vec[:, keep].astype(complex))
    kmax, mmax = float(np.max(np.abs(np.diag(K)))), float(np.max(np.diag(M)))
    s = np.sqrt(kmax / mmax) if kmax > 0.0 and mmax > 0.0 else 1.0
    eye, zero = np.eye(n), np.zeros((n, n))
    A = np.block([[zero, s * eye], [-K / s, -D]])
    B = np.block([[eye, zero], [zero, M]])
    lam, vec = scipy.linalg.eig(A, B, check_finite=False)
    finite = np.isfinite(lam)
    lam, vec = lam[finite], vec[:n, finite] / s
    if lam.size == 0:
        return np.zeros(0, dtype=complex), np.zeros((n, 0), dtype=complex)
    keep = lam.imag > ZERO_FREQUENCY_RTOL * float(np.max(np.abs(lam)))
    lam, vec = lam[keep], vec[:, keep]
    order = np.argsort(lam.imag, kind="stable")
    return lam[order], _normalise(vec[:, order])


def _weighted(shapes: NDArray[np.complex128], ell: float) -> NDArray[np.complex128]:
    """`shapes` with the rotations (dofs ``4 i + 2``, ``4 i + 3``) multiplied by `ell`."""
    out = shapes.copy()
    out[2::4] *= ell
    out[3::4] *= ell
    return out


def _mac(a: NDArray[np.complex128], b: NDArray[np.complex128], ell: float) -> NDArray[np.float64]:
    """``|a_i^H b_j|^2 / (|a_i|^2 |b_j|^2)`` for every pair of columns, rotations weighted by
    `ell` (clipped to 1 against round-off)."""
    a, b = _weighted(a, ell), _weighted(b, ell)
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return np.minimum(num / den, 1.0)


def _mac_columns(
    a: NDArray[np.complex128], b: NDArray[np.complex128], ell: float
) -> NDArray[np.float64]:
    """:func:`_mac` of the pairs of columns ``(a_j, b_j)`` only."""
    a, b = _weighted(a, ell), _weighted(b, ell)
    num = np.abs(np.sum(a.conj() * b, axis=0)) ** 2
    den = np.sum(np.abs(a) ** 2, axis=0) * np.sum(np.abs(b) ** 2, axis=0)
    return np.minimum(num / den, 1.0)


def _orbit_forms(
    v: NDArray[np.complex128], ell: float
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Hermitian forms ``(H, N)`` on the columns of `v`: the signed orbit area
    ``sum_nodes -Im(conj(X) Y) + ell^2 Im(conj(Theta_y) Theta_x)`` and the amplitude
    ``sum |X|^2 + |Y|^2 + ell^2 (|Theta_x|^2 + |Theta_y|^2)`` (see :func:`_whirl`)."""
    x, y, tx, ty = v[0::4], v[1::4], v[2::4], v[3::4]
    h = 0.5j * (x.conj().T @ y - y.conj().T @ x) + 0.5j * ell**2 * (
        ty.conj().T @ tx - tx.conj().T @ ty
    )
    g = x.conj().T @ x + y.conj().T @ y + ell**2 * (tx.conj().T @ tx + ty.conj().T @ ty)
    return (h + h.conj().T) / 2, (g + g.conj().T) / 2


def _circular_pairs(
    lam: NDArray[np.complex128], shapes: NDArray[np.complex128], ell: float
) -> NDArray[np.complex128]:
    """Within each cluster of equal eigenvalues (an axisymmetric rotor's pairs), choose the
    basis that extremises the orbit area: circular backward and forward orbits, not an
    arbitrary mix; shapes rescaled as in :func:`_complex_modes`."""
    out = shapes.copy()
    i = 0
    while i < lam.size:
        j = i
        while j + 1 < lam.size and abs(lam[j + 1] - lam[i]) <= CLUSTER_RTOL * abs(lam[i]):
            j += 1
        if j > i:
            v = out[:, i : j + 1]
            h, g = _orbit_forms(v, ell)
            _, c = scipy.linalg.eigh(h, g)
            out[:, i : j + 1] = _normalise(v @ c)
        i = j + 1
    return out


def _normalise(vec: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """Scale each column so that its translation of largest magnitude is 1 (all dofs if no
    translation moves)."""
    n = vec.shape[0]
    trans = np.zeros(n, dtype=bool)
    trans[0::4] = trans[1::4] = True
    out = vec.copy()
    for j in range(vec.shape[1]):
        v = vec[:, j]
        ref = np.where(trans, np.abs(v), 0.0)
        if ref.max() <= 1e-12 * np.abs(v).max():
            ref = np.abs(v)
        out[:, j] = v / v[int(np.argmax(ref))]
    return out


def _whirl(nodes: NDArray[np.complex128], ell: float) -> str:
    """Whirl sense of one mode from its node amplitudes ``(X, Y, Theta_x, Theta_y)``.

    A node orbits forward when its signed orbit area ``-Im(conj(X) Y)`` is positive (for
    ``x = Re(X e^{i w t})``, ``y = Re(Y e^{i w t})``, ``w > 0``: counter-clockwise from +x to
    +y, the spin's sense); tilts count through the axis direction ``(theta_y, -theta_x)``,
    weighted by ``ell^2`` (the mean element length).
    """
    X, Y, Tx, Ty = nodes.T
    area = -np.imag(np.conj(X) * Y) + ell**2 * np.imag(np.conj(Ty) * Tx)
    amp = np.abs(X) ** 2 + np.abs(Y) ** 2 + ell**2 * (np.abs(Tx) ** 2 + np.abs(Ty) ** 2)
    moving = amp >= NODE_RTOL * amp.max()
    signed = moving & (np.abs(area) > PLANAR_RTOL * amp)
    if not signed.any():
        return "planar"
    if np.all(area[signed] > 0.0):
        return "forward"
    if np.all(area[signed] < 0.0):
        return "backward"
    return "mixed"
