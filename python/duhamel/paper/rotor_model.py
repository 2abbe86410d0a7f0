"""The paper's rotor (section 4.4): its layout, parameters, damping, static scale and the
duhamel System of one case; see :mod:`duhamel.paper.rotor` for what the paper fixes and what
we chose."""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

import duhamel
from duhamel import rotor as R
from duhamel.paper._common import Array

__all__ = [
    "BEARING_NODES",
    "BETAS",
    "CONSIDERABLE",
    "COUPLING",
    "DISKS",
    "DT",
    "ELEMENT_LENGTHS",
    "FORCE",
    "FORCE_NODE",
    "K_CROSS",
    "K_DIRECT",
    "PAPER_CPU",
    "POSITIONS",
    "SHAFT_DIAMETER",
    "SMALL",
    "SPEED",
    "T_END",
    "XIS",
    "ZETA",
    "paper_dof",
    "paper_rotor",
    "paper_system",
    "static_scale",
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
    import scipy.linalg

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
    [7.2, 107.86, 105.74, 11.54, 54.2]
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
    >>> system
    System(n_dof=20, damping='rayleigh', loads=2, elements=4, couplings=2, mass_law)
    >>> system.mass_law.form
    'acceleration'
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
