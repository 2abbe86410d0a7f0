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

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from duhamel import elements, events, loads, mass, oscillator, speed
from duhamel._core import __version__
from duhamel.constants import STANDARD_GRAVITY
from duhamel.damping import Rayleigh
from duhamel.errors import (
    AccuracyWarning,
    DampingWarning,
    DuhamelError,
    InternalError,
    SolverError,
)
from duhamel.events import Event
from duhamel.integrators import (
    HHT,
    CentralDifference,
    CubicHermite,
    DirectIntegrator,
    GeneralizedAlpha,
    Newmark,
    Semianalytic,
)
from duhamel.prepared import Prepared, prepare, solve
from duhamel.results import ModalHistory, Solution, SolveStats
from duhamel.runs import RunSpec, SaveAt
from duhamel.store import resume
from duhamel.system import ModalBasis, System

if TYPE_CHECKING:
    from duhamel import analysis, design, ensemble, exact, opensees, records, rotor, spectra
    from duhamel import paper as paper  # lazy too, but not in __all__ (`import *` skips it)
    from duhamel.ensemble import solve_many

__all__ = [
    "HHT",
    "STANDARD_GRAVITY",
    "AccuracyWarning",
    "CentralDifference",
    "CubicHermite",
    "DampingWarning",
    "DirectIntegrator",
    "DuhamelError",
    "Event",
    "GeneralizedAlpha",
    "InternalError",
    "ModalBasis",
    "ModalHistory",
    "Newmark",
    "Prepared",
    "Rayleigh",
    "RunSpec",
    "SaveAt",
    "Semianalytic",
    "Solution",
    "SolveStats",
    "SolverError",
    "System",
    "__version__",
    "analysis",
    "design",
    "elements",
    "ensemble",
    "events",
    "exact",
    "loads",
    "mass",
    "opensees",
    "oscillator",
    "prepare",
    "records",
    "resume",
    "rotor",
    "solve",
    "solve_many",
    "spectra",
    "speed",
]

#: Subpackages imported on first access (PEP 562), so that ``import duhamel`` stays light:
#: they pull in scipy.optimize, scipy.special, scipy.signal ... which most runs never need.
_LAZY = frozenset(
    {"analysis", "design", "ensemble", "exact", "opensees", "paper", "records", "rotor", "spectra"}
)


#: Functions of those subpackages exported at the top level, loaded with them.
_LAZY_FUNCTIONS = {"solve_many": "ensemble"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        module = importlib.import_module(f"duhamel.{name}")
        globals()[name] = module
        return module
    if name in _LAZY_FUNCTIONS:
        value = getattr(importlib.import_module(f"duhamel.{_LAZY_FUNCTIONS[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'duhamel' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | _LAZY | set(_LAZY_FUNCTIONS))
