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

The model lives in :mod:`~duhamel.paper.rotor_model`, the orbits in
:mod:`~duhamel.paper.rotor_orbits`, Table 1 in :mod:`~duhamel.paper.rotor_table1`; this
module gathers them.

Examples
--------
>>> from duhamel.paper.rotor import paper_dof, paper_rotor
>>> [paper_dof(j) for j in (1, 2, 13, 14)]
[(0, 'x'), (0, 'y'), (3, 'x'), (3, 'y')]
>>> paper_rotor()
Rotor(nodes=5, n_dof=20, shafts=4, disks=3, bearings=2)
"""

# The model's other parameters (K_DIRECT, SHAFT_DIAMETER, ...) stay importable from here, as
# before the split, without joining __all__.
from duhamel.paper.rotor_model import (  # noqa: F401
    BEARING_NODES,
    BETAS,
    CONSIDERABLE,
    COUPLING,
    DISKS,
    DT,
    ELEMENT_LENGTHS,
    FORCE,
    FORCE_NODE,
    K_CROSS,
    K_DIRECT,
    PAPER_CPU,
    POSITIONS,
    SHAFT_DIAMETER,
    SMALL,
    SPEED,
    T_END,
    XIS,
    ZETA,
    paper_dof,
    paper_rotor,
    paper_system,
    static_scale,
)
from duhamel.paper.rotor_orbits import RotorOrbits, rotor_orbits
from duhamel.paper.rotor_table1 import Table1Data, table1

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
