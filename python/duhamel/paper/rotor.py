"""Section 4.4: the nonlinear rotor with variable mass (Figs. 9-13, Table 1).

What the paper fixes (NOTES.md section 4): 20 degrees of freedom from four rotating beam
elements and three rotor (disk) elements; bearing stiffness ``k11 = k22 = 1e9`` N/m and
``k12 = -k21 = 1e7`` N/m; the cubic bearing law ``r_i = k_ii x_i beta (x_i / x_stat)^2`` on
its degrees of freedom 1, 2, 13, 14 with ``beta = 0`` and ``0.1``; 1500 rpm; from rest, a
sudden eccentricity with the force ``F = 5e4`` N; the mass ``M(t) = M0 [1 + xi sin(nu t)]``
with ``nu`` the spin speed; results scaled by the static deflection under the rotor's own
weight (``beta = 0``); Table 1, the relative CPU time for 20, 15, 10, 5 and 3 modal
coordinates (100, 85, 60, 36, 27 %), and Newmark at about twice the CPU time of the full
model.

What it leaves open, and what we chose (docs/paper.md, "Section 4.4"):

* **Layout.** 5 nodes (4 Timoshenko elements, 4 dofs per node, :mod:`duhamel.rotor`). The
  paper's 1-based dof ``j`` is our node ``(j - 1) // 4``, direction ``(j - 1) % 4`` of
  ``(x, y, theta_x, theta_y)`` (:func:`paper_dof`): its bearing dofs 1, 2, 13, 14 are the
  ``x, y`` of nodes 0 and 3. The three disks sit on the three other nodes: the "left rotor"
  (node 1) and the "right rotor" (node 2) between the bearings, and an overhung disk (a
  coupling half, node 4).
* **Geometry and material** (:data:`ELEMENT_LENGTHS`, :data:`SHAFT_DIAMETER`,
  :data:`DISKS`): a solid steel shaft of 200 mm, bearing span 2.0 m, overhang 0.5 m; two
  disks of 552 kg (800 mm, 150 mm wide) and an overhung one of 193 kg (500 mm); 1911 kg in
  all. A machine of that size is what bearings of 1e9 N/m and a 1500 rpm speed belong to;
  its weight (18.7 kN) is of the order of the force (50 kN), so the scaled orbits are of
  order 1-10 and the cubic law with ``beta = 0.1`` is a correction, not a rigid stop. The
  first critical speeds are 265 and 273 rad/s (2530 and 2610 rpm) at 1500 rpm (157 rad/s).
* **Damping**: the paper's background damping "of the Rayleigh type", 2 % at the first two
  bending frequencies at rest.
* **The sudden eccentricity** is an unbalance switched on at ``t = 0`` whose force at
  1500 rpm is 5e4 N (``m_e = F / Omega^2 = 2.03`` kg m), on the right rotor (node 2, the
  middle of the three disks): ``eccentricity="rotating"``. ``eccentricity="fixed"`` is the
  other reading, a force of fixed direction (a :class:`~duhamel.rotor.SuddenForce` along
  ``x``).
* **Variable mass**: ``M(t) = M0 [1 + xi sin(Omega t)]`` on the whole mass matrix in the
  acceleration form ``M(t) x''`` (the paper's eqs. 1-2, ``M = m + M(X, X', t)``;
  ``form="momentum"`` is available), ``xi`` = 0, 0.05, 0.1; the weight stays ``M0 g``.
* **Gravity** along ``-y`` from ``t = 0``, like the force: the rotor starts from rest at the
  undeflected position ("homogeneous initial conditions").

Examples
--------
>>> from duhamel.paper.rotor import paper_dof, paper_rotor
>>> [paper_dof(j) for j in (1, 2, 13, 14)]
[(0, 'x'), (0, 'y'), (3, 'x'), (3, 'y')]
>>> paper_rotor()
Rotor(nodes=5, n_dof=20, shafts=4, disks=3, bearings=2)
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg

import duhamel
from duhamel import rotor as R
from duhamel.paper._common import Array, Claim, fit_order, fmt

__all__ = [
    "BETAS",
    "PAPER_CPU",
    "POSITIONS",
    "XIS",
    "RotorOrbits",
    "Table1Data",
    "paper_dof",
    "paper_rotor",
    "paper_system",
    "rotor_orbits",
    "static_scale",
    "table1",
]

#: Shaft element lengths (m), node 0 at the left bearing: bearing span 0.7 + 0.6 + 0.7 m,
#: overhang 0.5 m.
ELEMENT_LENGTHS = (0.7, 0.6, 0.7, 0.5)
#: Outer diameter of the solid shaft (m).
SHAFT_DIAMETER = 0.2
#: The three rigid disks: (node, width, outer diameter) in m, bored to the shaft diameter.
DISKS = ((1, 0.15, 0.8), (2, 0.15, 0.8), (4, 0.15, 0.5))
#: Bearing nodes: the paper's dofs 1, 2 (node 0) and 13, 14 (node 3).
BEARING_NODES = (0, 3)
#: The paper's bearing stiffness: direct k11 = k22, cross-coupled k12 = -k21 (N/m).
K_DIRECT = 1e9
K_CROSS = 1e7
#: Spin speed, 1500 rpm (rad/s).
SPEED = R.rpm(1500.0)
#: The sudden eccentricity: its force at 1500 rpm (N) and its node.
FORCE = 5e4
FORCE_NODE = 2
#: Rayleigh damping ratio at the first two bending frequencies at rest.
ZETA = 0.02
#: The cubic-law parameters and mass variations computed.
BETAS = (0.0, 0.1)
XIS = (0.0, 0.05, 0.1)
#: The positions of Figs. 10-13: (label, node).
POSITIONS = (
    ("left bearing", 0),
    ("right bearing", 3),
    ("left rotor", 1),
    ("right rotor", 2),
)
#: Step and duration of the runs (s): 400 steps per revolution, 12.5 revolutions.
DT = 1e-4
T_END = 0.5
#: Table 1 of the paper: relative CPU time (%) per number of modal coordinates.
#: The paper's route for the gyroscopic and cross-coupled terms: modal pseudo-forces (the
#: default ``coupling="auto"`` would integrate the linear cases exactly instead).
COUPLING = "pseudo-force"

PAPER_CPU = {20: 100.0, 15: 85.0, 10: 60.0, 5: 36.0, 3: 27.0}
#: "Considerably influences the motion": a change of at least this fraction of the orbit.
CONSIDERABLE = 0.1
#: "Small errors": at most this fraction of the orbit.
SMALL = 0.05

_ECCENTRICITIES = ("rotating", "fixed")


def paper_dof(j: int) -> tuple[int, str]:
    """The node and direction of the paper's 1-based degree of freedom `j` (1..20).

    The paper numbers 4 dofs per node from 1; we assume its per-node order is ours,
    ``(x, y, theta_x, theta_y)``, so ``j`` is node ``(j - 1) // 4``, direction
    ``(j - 1) % 4``.

    Examples
    --------
    >>> from duhamel.paper.rotor import paper_dof
    >>> paper_dof(13)
    (3, 'x')
    """
    if isinstance(j, bool) or not isinstance(j, int | np.integer) or not 1 <= j <= 20:
        raise ValueError(f"`j` must be an integer in 1..20, got {j!r}")
    return (int(j) - 1) // 4, tuple(R.DIRECTIONS)[(int(j) - 1) % 4]


@functools.cache
def _rayleigh() -> tuple[float, float]:
    """``(alpha, beta)`` of ``alpha M + beta K`` with ``ZETA`` at the first two distinct
    undamped frequencies of the background at rest (the lowest two bending pairs)."""
    rotor = _rotor(0.0, None)
    M, K = rotor.matrices().M, rotor.matrices().K
    omega = np.sqrt(scipy.linalg.eigh((K + K.T) / 2.0, M, eigvals_only=True))
    w1 = float(omega[0])
    w2 = float(omega[np.argmax(omega > w1 * (1.0 + 1e-6))])
    b = 2.0 * ZETA / (w1 + w2)
    return b * w1 * w2, b


def _rotor(beta: float, rayleigh: tuple[float, float] | None) -> R.Rotor:
    shafts = [R.Shaft(length, SHAFT_DIAMETER, material=R.STEEL) for length in ELEMENT_LENGTHS]
    disks = [
        R.Disk.from_geometry(node, width, outer, SHAFT_DIAMETER, R.STEEL)
        for node, width, outer in DISKS
    ]
    bearings = [
        R.Bearing(node, K_DIRECT, K_DIRECT, kxy=K_CROSS, kyx=-K_CROSS, beta=beta)
        for node in BEARING_NODES
    ]
    return R.Rotor(shafts, disks, bearings, rayleigh=rayleigh)


def paper_rotor(beta: float = 0.0) -> R.Rotor:
    """The rotor of section 4.4 with the cubic bearing law `beta` (``x_stat`` of each bearing:
    its static deflection under the weight with ``beta = 0``).

    Parameters
    ----------
    beta : float
        The paper's cubic-law parameter (0 or 0.1).

    Returns
    -------
    duhamel.rotor.Rotor
        5 nodes, 20 dofs, Rayleigh damping (2 % at the first two bending frequencies).

    Examples
    --------
    >>> from duhamel.paper.rotor import paper_rotor
    >>> rotor = paper_rotor(0.1)
    >>> round(rotor.mass, 1), [type(e).__name__ for e in rotor.nonlinear_elements()]
    (1910.7, ['Cubic', 'Cubic', 'Cubic', 'Cubic'])
    """
    return _rotor(float(beta), _rayleigh())


def static_scale(rotor: R.Rotor | None = None) -> Array:
    """The paper's scale: the magnitude of each node's vertical deflection under the rotor's
    own weight (m), ``beta = 0`` (:meth:`duhamel.rotor.Rotor.static_deflection`).

    Examples
    --------
    >>> from duhamel.paper.rotor import static_scale
    >>> [round(1e6 * float(s), 2) for s in static_scale()]  # micrometres, nodes 0..4
    [7.2, 107.9, 105.77, 11.54, 54.22]
    """
    rotor = paper_rotor(0.0) if rotor is None else rotor
    return np.abs(rotor.static_deflection()[1::4])


def paper_system(
    beta: float,
    xi: float,
    *,
    eccentricity: str = "rotating",
    form: str = "acceleration",
) -> duhamel.System:
    """The rotor at 1500 rpm with the sudden eccentricity, gravity and the mass law.

    Parameters
    ----------
    beta : float
        Cubic bearing law.
    xi : float
        Variable portion of the mass, ``M(t) = M0 [1 + xi sin(Omega t)]``; 0: constant mass.
    eccentricity : {"rotating", "fixed"}
        The sudden eccentricity as an unbalance turning with the shaft (force 5e4 N at
        1500 rpm) or as a force of fixed direction (5e4 N along x), on node 2.
    form : {"acceleration", "momentum"}
        ``M(t) x''`` or ``d/dt (M(t) x')``.

    Returns
    -------
    System

    Examples
    --------
    >>> from duhamel.paper.rotor import paper_system
    >>> system = paper_system(0.1, 0.05)
    >>> system, system.mass_law.form
    (System(n_dof=20, damping='rayleigh', loads=2, elements=6, mass_law), 'acceleration')
    """
    if eccentricity not in _ECCENTRICITIES:
        raise ValueError(f"`eccentricity` must be one of {_ECCENTRICITIES}, got {eccentricity!r}")
    rotor = paper_rotor(beta)
    force: R.RotorLoad
    if eccentricity == "rotating":
        force = R.Unbalance.from_force(FORCE_NODE, FORCE, SPEED)
    else:
        force = R.SuddenForce(FORCE_NODE, fx=FORCE)
    system = rotor.system(SPEED, [force, R.Gravity()])
    if xi != 0.0:
        system.set_mass_law(duhamel.mass.Harmonic(amplitude=xi, frequency=SPEED), form=form)
    return system


def _planar(x: Array, nodes: Sequence[int]) -> Array:
    """``(n_t, n_nodes, 2)``: the nodes' ``(x, y)`` from a displacement history."""
    idx = np.array([[4 * n, 4 * n + 1] for n in nodes])
    return x[:, idx]


def _relative_error(x: Array, ref: Array) -> Array:
    """Per position: ``max_t |r - r_ref| / max_t |r_ref|`` (``r`` the ``(x, y)`` vector)."""
    return np.linalg.norm(x - ref, axis=2).max(axis=0) / np.linalg.norm(ref, axis=2).max(axis=0)


@dataclass(frozen=True, eq=False)
class RotorOrbits:
    """Figs. 10-13: the orbits of the journal centres and the disk centres.

    Attributes
    ----------
    t : ndarray, shape (n_t,)
    orbits : dict of (beta, xi) to ndarray, shape (n_t, 4, 2)
        ``(x, y) / x_stat`` at the :data:`POSITIONS`, each scaled by its own static
        deflection under the weight (``beta = 0``).
    x_stat : ndarray, shape (4,)
        Those deflections (m).
    frequencies : ndarray
        Damped natural frequencies at 1500 rpm (rad/s), linear rotor.
    rayleigh : (float, float)
        The Rayleigh coefficients ``(alpha, beta)``.
    eccentricity, form : str
        As :func:`paper_system`.
    dt, t_end : float
    seconds : float
        Time for all runs (solve calls).
    """

    t: Array
    orbits: dict[tuple[float, float], Array]
    x_stat: Array
    frequencies: Array
    rayleigh: tuple[float, float]
    eccentricity: str
    form: str
    dt: float
    t_end: float
    seconds: float

    @property
    def betas(self) -> list[float]:
        """The ``beta`` values computed, ascending."""
        return sorted({b for b, _ in self.orbits})

    @property
    def xis(self) -> list[float]:
        """The ``xi`` values computed, ascending."""
        return sorted({x for _, x in self.orbits})

    def radius(self, beta: float, xi: float) -> Array:
        """Largest distance from the rest position at each position (units of ``x_stat``)."""
        return np.linalg.norm(self.orbits[(beta, xi)], axis=2).max(axis=0)

    def mass_influence(self, beta: float, xi: float) -> Array:
        """Per position: the largest change of the motion from ``xi = 0`` over the run,
        ``max_t |r_xi - r_0|``, over the orbit's size ``max_t |r_0|``."""
        return _relative_error(self.orbits[(beta, xi)], self.orbits[(beta, 0.0)])

    def claims(self) -> list[Claim]:
        """Statements of section 4.4 about Figs. 10-13, with our numbers."""
        labels = [p[0] for p in POSITIONS]
        b_lo, b_hi = self.betas[0], self.betas[-1]
        x_hi = self.xis[-1]
        r0, r1 = self.radius(b_lo, 0.0), self.radius(b_hi, 0.0)
        out = [
            Claim(
                "the model: 20 dofs, four rotating beam elements, three rotor elements; "
                "bearings (1e9, 1e7 N/m) at dofs 1, 2, 13, 14",
                "section 4.4, Fig. 9",
                "5 nodes; dofs 1, 2, 13, 14 = x, y of nodes 0 and 3; disks at nodes 1, 2, 4; "
                "critical speeds at 1500 rpm "
                + ", ".join(f"{w:.0f}" for w in self.frequencies[:4])
                + " rad/s; x_stat "
                + ", ".join(
                    f"{lab} {1e6 * s:.2f} um" for lab, s in zip(labels, self.x_stat, strict=True)
                )
                + f"; Rayleigh alpha {self.rayleigh[0]:.3g} 1/s, beta {self.rayleigh[1]:.3g} s",
                None,
                "geometry ours (the paper gives none): docs/paper.md",
            ),
            Claim(
                f"Figs. 10-11: the effect of the nonlinear restoring force (beta = {b_lo:g} "
                f"and {b_hi:g}) on the journal motion",
                "Figs. 10, 11",
                "largest orbit radius / x_stat, beta "
                f"{b_lo:g} -> {b_hi:g}: "
                + ", ".join(
                    f"{lab} {fmt(a)} -> {fmt(b)}" for lab, a, b in zip(labels, r0, r1, strict=True)
                ),
                None,
                "the cubic law stiffens the bearings: the journal orbits shrink and turn "
                "square (x and y laws are separate); the disks hardly notice",
            ),
        ]
        for beta in self.betas:
            if x_hi == 0.0:
                break
            change = self.mass_influence(beta, x_hi)
            envelope = np.abs(self.radius(beta, x_hi) / self.radius(beta, 0.0) - 1.0)
            out.append(
                Claim(
                    f"the variable mass considerably influences the motion of the rotor "
                    f"(beta = {beta:g}, xi = {x_hi:g} against xi = 0)",
                    "section 4.4, Figs. 10-13",
                    "largest change of the motion / orbit size: "
                    + ", ".join(
                        f"{lab} {100 * c:.1f} %" for lab, c in zip(labels, change, strict=True)
                    )
                    + "; of the largest radius: "
                    + ", ".join(f"{100 * e:.1f} %" for e in envelope),
                    bool(change.max() >= CONSIDERABLE),
                    f"holds = some position changes by >= {100 * CONSIDERABLE:.0f} % of its "
                    "orbit; the effect grows with (Omega / omega_1)^2 = "
                    f"{(SPEED / self.frequencies[0]) ** 2:.2f} here",
                )
            )
        return out


def rotor_orbits(
    betas: Sequence[float] = BETAS,
    xis: Sequence[float] = XIS,
    *,
    t_end: float = T_END,
    dt: float = DT,
    eccentricity: str = "rotating",
    form: str = "acceleration",
) -> RotorOrbits:
    """Data of Figs. 10-13: every ``(beta, xi)`` run with the full semi-analytic model.

    Parameters
    ----------
    betas, xis : sequence of float
        Cubic-law parameters and mass variations (``xi = 0`` is always computed: the other
        values are compared with it).
    t_end, dt : float
        Run length and step (s).
    eccentricity, form : str
        See :func:`paper_system`.

    Returns
    -------
    RotorOrbits

    Examples
    --------
    >>> from duhamel.paper.rotor import rotor_orbits
    >>> data = rotor_orbits(betas=(0.0,), xis=(0.0,), t_end=0.01)
    >>> data.orbits[(0.0, 0.0)].shape
    (101, 4, 2)
    """
    nodes = [n for _, n in POSITIONS]
    scale = static_scale()[nodes]
    xi_values = sorted({0.0, *map(float, xis)})
    orbits: dict[tuple[float, float], Array] = {}
    seconds = 0.0
    t = np.empty(0)
    for beta in map(float, betas):
        for xi in xi_values:
            system = paper_system(beta, xi, eccentricity=eccentricity, form=form)
            sol = duhamel.solve(system, duhamel.Semianalytic(coupling=COUPLING), t_end=t_end, dt=dt)
            seconds += sol.stats.total_time
            t = sol.t
            orbits[(beta, xi)] = _planar(sol.x, nodes) / scale[None, :, None]
    return RotorOrbits(
        t=t,
        orbits=orbits,
        x_stat=scale,
        frequencies=paper_rotor(0.0).natural_frequencies(SPEED),
        rayleigh=_rayleigh(),
        eccentricity=eccentricity,
        form=form,
        dt=float(dt),
        t_end=float(t_end),
        seconds=seconds,
    )


@dataclass(frozen=True, eq=False)
class Table1Data:
    """Table 1: modal reduction (CPU time, error against the full model) and Newmark.

    Attributes
    ----------
    modes : tuple of int
        Retained modes, the first the full model (20).
    seconds : dict of int to ndarray
        Loop time (:attr:`duhamel.SolveStats.wall_time`, s) of every repeat per mode count.
    newmark_seconds : ndarray
        Loop time of ``duhamel.Newmark()`` at the same step, every repeat.
    errors : dict of int to ndarray, shape (4,)
        Per position (:data:`POSITIONS`), ``max_t |r_m - r_full| / max_t |r_full|`` of the
        paper's case (``beta``, ``xi``).
    linear_errors : dict of int to ndarray, shape (4,)
        The same for the linear rotor (``beta = 0``, ``xi = 0``).
    accuracy : dict of str to float
        Largest error over the positions against a converged run (the full semi-analytic
        model at ``dt / refine``), in units of the orbit size: ``"semi-analytic"`` and
        ``"Newmark"`` at ``dt``, ``"Newmark dt/k"`` at the finer steps tried.
    newmark_equal : tuple of (int, float, bool)
        The smallest ``k`` for which Newmark at ``dt / k`` is as accurate as the
        semi-analytic method at ``dt``, its loop time (s), and whether it was reached (else
        the largest ``k`` tried).
    beta, xi, dt, t_end : float
    steps : int
    repeats : int
    refine : int
    """

    modes: tuple[int, ...]
    seconds: dict[int, Array]
    newmark_seconds: Array
    errors: dict[int, Array]
    linear_errors: dict[int, Array]
    accuracy: dict[str, float]
    newmark_equal: tuple[int, float, bool]
    beta: float
    xi: float
    dt: float
    t_end: float
    steps: int
    repeats: int
    refine: int

    @property
    def full(self) -> int:
        """The full model's number of modes."""
        return self.modes[0]

    def relative_cpu(self, m: int) -> float:
        """Best loop time with `m` modes over the full model's, in %."""
        return 100.0 * float(self.seconds[m].min() / self.seconds[self.full].min())

    @property
    def newmark_ratio(self) -> float:
        """Best Newmark loop time over the full semi-analytic model's, same step."""
        return float(self.newmark_seconds.min() / self.seconds[self.full].min())

    def cost_exponent(self) -> float:
        """Slope of log(best loop time) against log(modes) over every mode count."""
        return fit_order(self.modes, [self.seconds[m].min() for m in self.modes])

    def claims(self) -> list[Claim]:
        """Table 1 and the statements of section 4.4 and the conclusion about it."""
        bearings, disks = slice(0, 2), slice(2, 4)
        out = []
        for m in self.modes:
            e, lin = self.errors[m], self.linear_errors[m]
            paper = f"{PAPER_CPU[m]:.0f} %" if m in PAPER_CPU else "-"
            out.append(
                Claim(
                    f"Table 1: {m} modal coordinates",
                    f"relative CPU time {paper}",
                    f"relative loop time {self.relative_cpu(m):.0f} % "
                    f"({1e6 * self.seconds[m].min() / self.steps:.1f} us per step); "
                    f"error bearings {100 * e[bearings].max():.1f} %, disks "
                    f"{100 * e[disks].max():.1f} % (linear rotor: "
                    f"{100 * lin[bearings].max():.1f} %, {100 * lin[disks].max():.1f} %)",
                    None,
                    "error = max_t |r_m - r_full| / max_t |r_full| per position",
                )
            )
        reduced = [m for m in self.modes if m != self.full]
        ours = "/".join(f"{self.relative_cpu(m):.0f}" for m in self.modes)
        theirs = "/".join(f"{PAPER_CPU.get(m, float('nan')):.0f}" for m in self.modes)
        near = all(
            abs(self.relative_cpu(m) - PAPER_CPU[m]) <= 10.0 for m in self.modes if m in PAPER_CPU
        )
        five = [m for m in self.modes if m >= 5 and m != self.full]
        worst_five = max((float(self.errors[m].max()) for m in five), default=0.0)
        acc = self.accuracy
        k, t_eq, reached = self.newmark_equal
        out += [
            Claim(
                "relative CPU time 100/85/60/36/27 % for 20/15/10/5/3 modal coordinates",
                "Table 1",
                f"{ours} % (cost ~ modes^{self.cost_exponent():.2f})",
                near,
                "holds = every value within 10 percentage points; the loop time falls "
                + (
                    "monotonically"
                    if all(
                        self.seconds[a].min() > self.seconds[b].min()
                        for a, b in itertools.pairwise(self.modes)
                    )
                    else "but not monotonically"
                )
                + f" with fewer modes; paper {theirs} %",
            ),
            Claim(
                "modal reduction gives only small errors with at least five generalized "
                "coordinates",
                "section 4.4",
                "largest error with "
                + ", ".join(f"{m}: {100 * self.errors[m].max():.1f} %" for m in five)
                + " modes",
                worst_five <= SMALL,
                f"holds = <= {100 * SMALL:.0f} % of the orbit at every position; beta = "
                f"{self.beta:g}, xi = {self.xi:g}. Linear rotor: "
                + ", ".join(f"{m}: {100 * self.linear_errors[m].max():.1f} %" for m in five),
            ),
            Claim(
                "the higher errors occur at the bearings",
                "section 4.4",
                ", ".join(
                    f"{m}: {100 * self.errors[m][bearings].max():.1f} vs "
                    f"{100 * self.errors[m][disks].max():.1f} %"
                    for m in reduced
                ),
                all(self.errors[m][bearings].max() > self.errors[m][disks].max() for m in reduced),
                "bearings vs disks, largest error of each; holds = at every reduced model",
            ),
            Claim(
                "Newmark takes about two times the computation time of the present method "
                "without modal reduction",
                "section 4.4",
                f"Newmark / semi-analytic (full) = {self.newmark_ratio:.2f} "
                f"({1e6 * self.newmark_seconds.min() / self.steps:.1f} vs "
                f"{1e6 * self.seconds[self.full].min() / self.steps:.1f} us per step)",
                bool(1.5 <= self.newmark_ratio <= 2.5),
                f"same step dt = {fmt(self.dt)} s, {self.steps} steps, best of "
                f"{self.repeats} interleaved runs, time loop only, one Rust engine; holds = "
                "ratio in [1.5, 2.5]",
            ),
            Claim(
                "at the same time step the error against a converged solution is smaller "
                "than Newmark's",
                "section 5",
                f"semi-analytic {fmt(acc['semi-analytic'])} vs Newmark {fmt(acc['Newmark'])} "
                "of the orbit size",
                acc["semi-analytic"] < acc["Newmark"],
                f"converged: the full semi-analytic model at dt/{self.refine}",
            ),
            Claim(
                "(not in the paper) cost at equal accuracy",
                "-",
                ("Newmark needs" if reached else "Newmark, not yet as accurate, at")
                + f" dt/{k} ({fmt(acc[f'Newmark dt/{k}'])}) to match the "
                f"semi-analytic method at dt: loop time {1e3 * t_eq:.1f} ms vs "
                f"{1e3 * self.seconds[self.full].min():.1f} ms, ratio "
                f"{t_eq / self.seconds[self.full].min():.2f}",
                None,
                "Newmark at dt/k, k = 1, 2, 3, ... until its error is at most the "
                "semi-analytic one",
            ),
        ]
        return out


def table1(
    modes: Sequence[int] = (20, 15, 10, 5, 3),
    *,
    beta: float = 0.1,
    xi: float = 0.1,
    t_end: float = T_END,
    dt: float = DT,
    repeats: int = 7,
    refine: int = 16,
    max_newmark_refine: int = 8,
) -> Table1Data:
    """Data of Table 1: modal reduction and Newmark on the paper's case.

    The runs of the mode counts and of Newmark are interleaved (one of each, `repeats`
    times) so that they see the same machine load; the time is the Rust loop's own clock
    (:attr:`duhamel.SolveStats.wall_time`, every step saved). Errors are against the full
    model at the same step (reduction) or against it at ``dt / refine`` (accuracy).

    Parameters
    ----------
    modes : sequence of int
        Retained modes; the first is the full model (20).
    beta, xi : float
        The case (the paper's: cubic bearings and variable mass).
    t_end, dt : float
        Run length and step (s).
    repeats : int
        Timed runs per method.
    refine : int
        The converged reference uses ``dt / refine``.
    max_newmark_refine : int
        Largest ``k`` tried for Newmark at ``dt / k`` (equal accuracy).

    Returns
    -------
    Table1Data

    Examples
    --------
    >>> from duhamel.paper.rotor import table1
    >>> data = table1(modes=(20, 10), t_end=0.02, repeats=1, refine=2)
    >>> data.errors[20].tolist()
    [0.0, 0.0, 0.0, 0.0]
    """
    modes = tuple(int(m) for m in modes)
    nodes = [n for _, n in POSITIONS]
    scale = static_scale()[nodes][None, :, None]
    system = paper_system(beta, xi)
    linear = paper_system(0.0, 0.0)
    kw = {"t_end": t_end, "dt": dt}
    seconds: dict[int, list[float]] = {m: [] for m in modes}
    newmark: list[float] = []
    runs: dict[int, Array] = {}
    steps = 0
    for _ in range(int(repeats)):
        for m in modes:
            sol = duhamel.solve(system, duhamel.Semianalytic(modes=m, coupling=COUPLING), **kw)
            seconds[m].append(sol.stats.wall_time)
            runs[m] = _planar(sol.x, nodes) / scale
            steps = sol.stats.steps
        sol = duhamel.solve(system, duhamel.Newmark(), **kw)
        newmark.append(sol.stats.wall_time)
        newmark_run = _planar(sol.x, nodes) / scale
    full = runs[modes[0]]
    errors = {m: _relative_error(runs[m], full) for m in modes}
    linear_runs = {
        m: _planar(
            duhamel.solve(linear, duhamel.Semianalytic(modes=m, coupling=COUPLING), **kw).x, nodes
        )
        / scale
        for m in modes
    }
    linear_errors = {m: _relative_error(linear_runs[m], linear_runs[modes[0]]) for m in modes}
    fine = duhamel.solve(
        system, duhamel.Semianalytic(coupling=COUPLING), t_end=t_end, dt=dt / refine
    )
    ref = _planar(fine.x[::refine], nodes) / scale
    accuracy = {
        "semi-analytic": float(_relative_error(full, ref).max()),
        "Newmark": float(_relative_error(newmark_run, ref).max()),
    }
    accuracy["Newmark dt/1"] = accuracy["Newmark"]
    equal = (1, float(min(newmark)), accuracy["Newmark"] <= accuracy["semi-analytic"])
    k = 1
    while not equal[2] and k < int(max_newmark_refine):
        k += 1
        sol = duhamel.solve(system, duhamel.Newmark(), t_end=t_end, dt=dt / k)
        err = float(_relative_error(_planar(sol.x[::k], nodes) / scale, ref).max())
        accuracy[f"Newmark dt/{k}"] = err
        equal = (k, sol.stats.wall_time, err <= accuracy["semi-analytic"])
    return Table1Data(
        modes=modes,
        seconds={m: np.array(v) for m, v in seconds.items()},
        newmark_seconds=np.array(newmark),
        errors=errors,
        linear_errors=linear_errors,
        accuracy=accuracy,
        newmark_equal=equal,
        beta=float(beta),
        xi=float(xi),
        dt=float(dt),
        t_end=float(t_end),
        steps=int(steps),
        repeats=int(repeats),
        refine=int(refine),
    )
