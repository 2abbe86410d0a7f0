"""duhamel: transient response of structural and rotordynamic systems.

``M x'' + C x' + K x = f(t)`` is integrated by the semi-analytic ("BEM in time") method of
Holl, Belyaev and Irschik (1999): every modal oscillator is stepped with its exact transition
and load-transfer matrices (Duhamel's integral), computed in a Rust core.

Examples
--------
>>> import numpy as np, duhamel
>>> sys = duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]]), zeta=0.05)
>>> _ = sys.add_load(duhamel.loads.Step(dof=1, amplitude=1.0))
>>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=20.0, dt=0.05)
>>> sol.x.shape
(401, 2)
"""

from duhamel import analysis, elements, exact, loads, mass, oscillator, rotor, speed
from duhamel._core import __version__
from duhamel.errors import DuhamelError, SolverError
from duhamel.integrators import (
    HHT,
    CentralDifference,
    CubicHermite,
    DirectIntegrator,
    GeneralizedAlpha,
    Newmark,
    Semianalytic,
)
from duhamel.solution import ModalHistory, Solution, SolveStats
from duhamel.solve import solve
from duhamel.system import ModalBasis, System

__all__ = [
    "HHT",
    "CentralDifference",
    "CubicHermite",
    "DirectIntegrator",
    "DuhamelError",
    "GeneralizedAlpha",
    "ModalBasis",
    "ModalHistory",
    "Newmark",
    "Semianalytic",
    "Solution",
    "SolveStats",
    "SolverError",
    "System",
    "__version__",
    "analysis",
    "elements",
    "exact",
    "loads",
    "mass",
    "oscillator",
    "rotor",
    "solve",
    "speed",
]
