"""Time integrators: small configuration objects passed to :func:`duhamel.solve`.

:class:`Semianalytic` runs the engine's modal routes; the direct integrators
(:class:`DirectIntegrator`: the generalized-alpha family and the cubic Hermite element) step
the physical equations. All share :class:`Integrator` (Newton's ``tol`` and ``max_iter``).
"""

from duhamel.integrators.alpha import HHT, CentralDifference, GeneralizedAlpha, Newmark
from duhamel.integrators.base import DirectIntegrator, Integrator
from duhamel.integrators.hermite import CubicHermite
from duhamel.integrators.semianalytic import Semianalytic

__all__ = [
    "HHT",
    "CentralDifference",
    "CubicHermite",
    "DirectIntegrator",
    "GeneralizedAlpha",
    "Integrator",
    "Newmark",
    "Semianalytic",
]
