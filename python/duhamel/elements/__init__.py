"""Force elements: restoring forces ``r(x, x', t)`` on the left-hand side,
``M x'' + C x' + K x + r(x, x', t) = f(t)``, added with :meth:`duhamel.System.add`.

Every element except :class:`Callable` is defined once, in Rust (its parameters, checks,
force and tangents, internal variables), and evaluated there with analytic tangents; the
classes here are those definitions. Where an element acts comes first: the dofs of a
deformation ``x_i - x_j`` as ``i, j`` (``j=None``: to the ground), or the dofs of a device
on several as one tuple ``dofs``; indices or dof labels. Physical parameters are
keyword-only (docs/models.md). :class:`PDelta` is no force element: it is linear, and
:meth:`duhamel.System.add` takes it into the stiffness. :class:`LinearCoupling`
(:mod:`duhamel.couplings`) is a coupling of the background, kept by a system apart from its
elements (:attr:`duhamel.System.couplings`). :func:`drive` drives an element through a
deformation history (a material test).
"""

from __future__ import annotations

from duhamel._core import (
    Bilinear,
    BoucWen,
    BreathingCrack,
    Callable,
    Contact,
    Cubic,
    Damper,
    ElasticMultiLinear,
    Element,
    FrictionPendulum,
    Gap,
    Hysteretic,
    IMKBilin,
    JournalElement,
    LeadRubberBearing,
    MinMax,
    ModIMKPeakOriented,
    MultiLinear,
    Parallel,
    Pinching4,
    Polynomial,
    Series,
    SpeedTableBearing,
    Spring,
    Steel02,
    Takeda,
    TripleFrictionPendulum,
    ViscousDamper,
)
from duhamel.couplings import LinearCoupling
from duhamel.elements.drive import Hysteresis, drive
from duhamel.elements.geometric import PDelta

__all__ = [
    "Bilinear",
    "BoucWen",
    "BreathingCrack",
    "Callable",
    "Contact",
    "Cubic",
    "Damper",
    "ElasticMultiLinear",
    "Element",
    "FrictionPendulum",
    "Gap",
    "Hysteresis",
    "Hysteretic",
    "IMKBilin",
    "JournalElement",
    "LeadRubberBearing",
    "LinearCoupling",
    "MinMax",
    "ModIMKPeakOriented",
    "MultiLinear",
    "PDelta",
    "Parallel",
    "Pinching4",
    "Polynomial",
    "Series",
    "SpeedTableBearing",
    "Spring",
    "Steel02",
    "Takeda",
    "TripleFrictionPendulum",
    "ViscousDamper",
    "drive",
]
