"""The rotor model: its components, matrices, duhamel System, modes and Campbell diagram.

Degrees of freedom: 4 per node, node ``i`` owning ``4 i + (0, 1, 2, 3)`` =
``(x, y, theta_x, theta_y)``; the shaft axis is z, nodes are numbered along it, and the
rotations are right-handed about the fixed x and y axes (so ``theta_y = dx/dz`` and
``theta_x = -dy/dz`` in pure bending). The shaft spins about +z at ``speed`` (rad/s); forward
whirl is an orbit in the sense of the spin, from +x towards +y. This is the convention of
Friswell, Penny, Garvey and Lees, *Dynamics of Rotating Machines* (2010), chapter 5.

Each component owns its matrices and dof mapping; assembly, modes, Campbell diagram and
transient System live in modules of those names; :class:`Rotor` ties them together."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._core import Element
from duhamel._engine.validate import finite_float
from duhamel.constants import STANDARD_GRAVITY
from duhamel.loads import Load
from duhamel.rotor._analyses import RotorAnalyses
from duhamel.rotor._equilibrium import (
    check_journal_nodes,
    journal_matrices,
    journal_parts,
    split_journals,
)
from duhamel.rotor._speed import constant_speed, speed_or_law
from duhamel.rotor._speed_table import speed_table_elements
from duhamel.rotor.assembly import Assembly, RotorMatrices
from duhamel.rotor.bearing import Bearing
from duhamel.rotor.campbell import Campbell
from duhamel.rotor.components import checked_components, placements
from duhamel.rotor.critical_map import CriticalSpeedMap
from duhamel.rotor.damping import damping_spec, structural_damping
from duhamel.rotor.disk import Disk
from duhamel.rotor.dofs import DIRECTIONS, dof_index
from duhamel.rotor.journal import ShortJournalBearing
from duhamel.rotor.loads import Gravity, RotorLoad
from duhamel.rotor.magnetic import split_magnetic
from duhamel.rotor.modes import Modes
from duhamel.rotor.shaft import Shaft
from duhamel.rotor.transient import (
    add_couplings,
    add_rotor_loads,
    background,
    bearing_elements,
    storage,
)
from duhamel.system import System

__all__ = ["DIRECTIONS", "Campbell", "Modes", "Rotor", "RotorMatrices"]


class Rotor(RotorAnalyses):
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
        every method that takes a speed evaluates there; also :class:`ShortJournalBearing`
        and :class:`MagneticBearing` (closed loops with their controllers' states).
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
        self.shafts: tuple[Shaft, ...]
        self.disks: tuple[Disk, ...]
        self.bearings: tuple[Bearing, ...]
        #: The nonlinear :class:`ShortJournalBearing` s given among `bearings`.
        self.journals: tuple[ShortJournalBearing, ...]
        linear, self.journals = split_journals(bearings)
        linear, self.magnetic = split_magnetic(linear)
        self.shafts, self.disks, self.bearings = checked_components(shafts, disks, linear)
        check_journal_nodes((*self.journals, *self.magnetic), self.n_nodes)
        self._zeta, self._rayleigh = damping_spec(zeta, rayleigh, self.n_dof)

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
    def mass_matrix(self) -> NDArray[np.float64]:
        """The mass matrix ``M`` (a copy; speed-independent)."""
        return self._assembly.M.copy()

    @property
    def dof_labels(self) -> tuple[str, ...]:
        """Name of each dof: ``x_0, y_0, theta_x_0, theta_y_0, x_1, ...`` (its system's
        :attr:`~duhamel.System.dof_labels`)."""
        return tuple(f"{d}_{node}" for node in range(self.n_nodes) for d in DIRECTIONS)

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
        return dof_index(node, direction, self.n_nodes)

    def __repr__(self) -> str:
        return (
            f"Rotor(nodes={self.n_nodes}, n_dof={self.n_dof}, shafts={len(self.shafts)}, "
            f"disks={len(self.disks)}, bearings={len(self.bearings)}"
            + (f", journals={len(self.journals)}" if self.journals else "")
            + (f", magnetic={len(self.magnetic)}" if self.magnetic else "")
            + ")"
        )

    # ------------------------------------------------------------------ assembly
    @cached_property
    def _assembly(self) -> Assembly:
        """The components placed at their nodes (shaft ``i`` at node ``i``) and assembled:
        shafts and disks as the structure, bearings as the supports."""
        structure, supports = placements(self.shafts, self.disks, self.bearings)
        return Assembly(structure, supports, self.n_dof)

    @property
    def has_speed_dependent_bearings(self) -> bool:
        """Whether any bearing has coefficients tabulated against the spin speed."""
        return bool(self._assembly.varying)

    def _massless_nodes(self) -> list[int]:
        diag = np.diag(self._assembly.M).reshape(self.n_nodes, 4)
        return [int(i) for i in np.flatnonzero(np.any(diag <= 0.0, axis=1))]

    def structural_damping(self, speed: float = 0.0) -> NDArray[np.float64]:
        """The structural damping matrix (without the bearings): ``alpha M + beta K_sym``,
        or ``M Phi diag(2 zeta omega) Phi^T M`` from the mass-normalised undamped modes of
        ``(K_sym, M)`` (rigid-body modes get none), or zero.

        ``K_sym`` (shaft + symmetric part of the bearing stiffness) is taken at spin speed
        `speed` (rad/s), which matters only with speed-dependent bearings.

        Examples
        --------
        >>> from duhamel.rotor import STEEL, Bearing, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.5, 0.05, material=STEEL)] * 2,
        ...               bearings=[Bearing(0, 1e7, 1e7), Bearing(2, 1e7, 1e7)],
        ...               rayleigh=(2.0, 0.0))
        >>> bool((rotor.structural_damping() == 2.0 * rotor.matrices().M).all())
        True
        """
        w = finite_float(speed, "speed")
        a = self._assembly
        if not a.varying:
            return self._structural_damping.copy()
        return self._structural(a.k_sym(a.supports_at(w)[0]))

    @cached_property
    def _structural_damping(self) -> NDArray[np.float64]:
        return self._structural(self._assembly.k_sym(self._assembly.K_support))

    def _structural(self, k_sym: NDArray[np.float64]) -> NDArray[np.float64]:
        return structural_damping(
            self._assembly.M,
            k_sym,
            zeta=self._zeta,
            rayleigh=self._rayleigh,
            massless_nodes=self._massless_nodes() if self._zeta is not None else None,
        )

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
        mats = self._linear_matrices(w)
        if not self.journals:
            return mats
        k_j, c_j = journal_matrices(self, w)
        return RotorMatrices(mats.M, mats.K + k_j, mats.C + c_j, mats.G)

    def _linear_matrices(self, w: float) -> RotorMatrices:
        """:meth:`matrices` without the journal bearings."""
        a = self._assembly
        kb, cb = a.supports_at(w)
        K = a.K_structure + kb
        C = self.structural_damping(w) + cb
        return RotorMatrices(a.M.copy(), K, C, a.G.copy())

    def static_deflection(
        self, g: float = STANDARD_GRAVITY, *, speed: float = 0.0
    ) -> NDArray[np.float64]:
        """Linear static deflection under the rotor's own weight (along ``-y``), ``K^-1 f_g``,
        with the full linear stiffness (nonlinear bearing parts left out) at spin speed
        `speed` (rad/s, keyword only; it matters only with speed-dependent bearings).

        Examples
        --------
        >>> from duhamel.rotor import STEEL, Bearing, Rotor, Shaft
        >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)],
        ...               bearings=[Bearing(0, 1e6, 1e6), Bearing(1, 1e6, 1e6)])
        >>> round(float(rotor.static_deflection()[1]) * 1e6, 3)   # at a bearing: -m g / (2 k)
        -75.192

        Bearings twice as stiff at 1000 rad/s as at rest:

        >>> fluid = [Bearing(n, [1e6, 2e6], [1e6, 2e6], speeds=[0, 1000]) for n in (0, 1)]
        >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)], bearings=fluid)
        >>> round(float(rotor.static_deflection(speed=1000.0)[1]) * 1e6, 3)
        -37.596
        """
        import scipy.linalg

        K = self.matrices(constant_speed(speed)).K
        f = Gravity(g=g).vector(self)
        try:
            return np.asarray(scipy.linalg.solve(K, f), dtype=np.float64)
        except (np.linalg.LinAlgError, scipy.linalg.LinAlgError) as exc:
            raise ValueError(
                "the rotor's stiffness matrix is singular: is it supported by `bearings`?"
            ) from exc

    def critical_speed_map(
        self,
        stiffnesses: ArrayLike,
        *,
        n_modes: int = 4,
        gyroscopic: bool = True,
        speeds: ArrayLike | None = None,
    ) -> CriticalSpeedMap:
        """Undamped critical speed map: the critical speeds with every bearing (and journal)
        replaced by an isotropic spring of each of `stiffnesses` on its node's x and y (no
        damping, no cross-coupling), the bearings' ``kxx`` and ``kyy`` against speed over
        them, and their intersections.

        Parameters
        ----------
        stiffnesses : array_like
            Increasing support stiffnesses (N/m).
        n_modes : int
            Keyword only. Critical speeds per stiffness.
        gyroscopic : bool
            Keyword only. Synchronous forward whirl (the spin equal to the whirl frequency,
            :func:`~duhamel.rotor.critical_map.undamped_critical_speeds`), or the rotor at rest.
        speeds : array_like, optional
            Keyword only. Speeds (rad/s) of the bearings' curves (default 241 from 0 to 1.2
            times the highest critical speed shown); the intersections are bracketed on them
            and refined by Brent's method on the eigenproblem. Beyond a bearing's table its
            end values are held, as everywhere, here without a ``TableRangeWarning``.

        Returns
        -------
        CriticalSpeedMap

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(n, [5e6, 2e7], [4e6, 1.6e7], speeds=[0, 3000]) for n in (0, 4)])
        >>> ucs = rotor.critical_speed_map(np.logspace(5, 9, 41), n_modes=2)
        >>> ucs.critical_speeds.shape
        (41, 2)
        >>> [(p.node, p.direction, p.mode, round(p.speed, 1)) for p in ucs.intersections][:2]
        [(0, 'kyy', 0, 246.9), (4, 'kyy', 0, 246.9)]
        """
        from duhamel.rotor.critical_map import critical_speed_map

        nodes = sorted({b.node for b in self.bearings} | {j.node for j in self.journals})
        if not nodes:
            raise ValueError("the rotor has no bearings: a critical speed map needs supports")
        a = self._assembly
        supports = [(self.dof(n, "x"), self.dof(n, "y")) for n in nodes]
        return critical_speed_map(
            a.M, a.K_structure, a.G, supports, self.bearings, stiffnesses,
            n_modes=n_modes, gyroscopic=gyroscopic, speeds=speeds,
            length_scale=float(np.mean([s.L for s in self.shafts])) if self.shafts else 1.0,
        )  # fmt: skip

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
          for a rub; each :class:`ShortJournalBearing` as a ``JournalElement`` following the
          speed (law), its stiffness and damping linearised at the static equilibrium of the
          initial speed carried by the background instead (start the run from
          :meth:`static_equilibrium` with :class:`Gravity` among the loads).
        * Along a varying law, each speed-dependent bearing's change from its initial
          coefficients as an element following the law.
        * `loads`: rotor loads (:class:`Unbalance`, :class:`Gravity`, :class:`SuddenForce`;
          an ``Unbalance`` without its own speed takes `speed`, a run-up included) and plain
          :mod:`duhamel.loads`.

        Parameters
        ----------
        speed : float or speed law
            Spin speed (rad/s), or a :mod:`duhamel.speed` law (``ConstantSpeed``, or
            ``LinearRunUp`` for a run-up or run-down). Along a varying law the
            speed-dependent bearings follow the speed (their coefficients at the initial
            speed in the background, the change as an element); the structural damping
            (Rayleigh or modal, built on ``K_sym``) is that of the initial speed.
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
            If a node has no mass (``rho = 0`` shafts without a disk there), or an
            ``Unbalance`` has a speed other than `speed`.
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
        # where the bearings are evaluated: the speed, or a run-up's initial speed (the
        # speed-dependent bearings then follow the law as elements, less these values)
        w_const = w if isinstance(w, float) else float(w.omega(0.0))
        tables = [] if isinstance(w, float) else speed_table_elements(self, w, w_const)
        massless = self._massless_nodes()
        if massless:
            raise ValueError(
                f"nodes {massless} have no mass (shafts whose material has `rho` = 0 and no "
                "disk there); a "
                "time integration needs mass at every degree of freedom"
            )
        a = self._assembly
        kb, cb = a.supports_at(w_const)
        journals = journal_parts(self, w)  # linearised at the equilibrium, into the background
        for part in journals:
            kb, cb = kb + part.K, cb + part.C
        M, k_sym = a.M, a.k_sym(kb)
        k_skew, c_skew = (kb - kb.T) / 2.0, (cb - cb.T) / 2.0
        c_sym = (cb + cb.T) / 2.0
        conv = storage(sparse)
        system = background(
            M,
            k_sym,
            c_sym,
            lambda: self.structural_damping(w_const),
            zeta=self._zeta,
            rayleigh=self._rayleigh,
            conv=conv,
        )
        add_couplings(system, a.G, w, k_skew, c_skew, conv, self.magnetic, self.dof)
        for element in self.nonlinear_elements(w_const):
            system.add(element)
        for part in journals:
            system.add(part.element)
        for element in tables:
            system.add(element)
        add_rotor_loads(system, self, loads, w)
        return system.label_dofs(self.dof_labels)

    def nonlinear_elements(self, speed: float = 0.0) -> list[Element]:
        """The bearings' nonlinear parts as :mod:`duhamel.elements` (global dofs).

        A cubic law without its own ``x_stat`` uses the magnitude of the bearing's vertical
        deflection in :meth:`static_deflection` (at standard gravity,
        :data:`duhamel.constants.STANDARD_GRAVITY`). `speed` (rad/s) is where speed-dependent
        bearings are evaluated (the static deflection, and ``kxx``, ``kyy`` of a cubic law);
        it does not matter otherwise.
        """
        w = constant_speed(speed)
        return bearing_elements(self.bearings, self.dof, lambda: self.static_deflection(speed=w), w)
