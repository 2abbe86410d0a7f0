"""Force elements: restoring forces ``r(x, x', t)`` on the left-hand side,
``M x'' + C x' + K x + r(x, x', t) = f(t)``, added with :meth:`duhamel.System.add`.

Every element except :class:`Callable` is evaluated in Rust with analytic tangents. The
integrator treats the element forces as modal pseudo-forces; :class:`LinearCoupling` is
projected on the modes once. The hysteretic and device elements of earthquake engineering
(:class:`Bilinear`, :class:`BoucWen`, :class:`FrictionPendulum`,
:class:`LeadRubberBearing`, :class:`ViscousDamper`, :class:`Gap`) are defined in
:mod:`.devices` (the triple friction pendulum :class:`TripleFrictionPendulum` in
:mod:`.triple`), the others in :mod:`.basic`, their base class in :mod:`.base`; all are
exported here. :class:`PDelta` (in :mod:`.geometric`) is no force element: it is linear,
and :meth:`duhamel.System.add` takes it into the stiffness.
"""

from __future__ import annotations

from duhamel.elements.base import Element
from duhamel.elements.basic import (
    Callable,
    Contact,
    Cubic,
    Damper,
    LinearCoupling,
    Polynomial,
    Spring,
)
from duhamel.elements.devices import (
    Bilinear,
    BoucWen,
    FrictionPendulum,
    Gap,
    LeadRubberBearing,
    ViscousDamper,
)
from duhamel.elements.geometric import PDelta
from duhamel.elements.triple import TripleFrictionPendulum

__all__ = [
    "Bilinear",
    "BoucWen",
    "Callable",
    "Contact",
    "Cubic",
    "Damper",
    "Element",
    "FrictionPendulum",
    "Gap",
    "LeadRubberBearing",
    "LinearCoupling",
    "PDelta",
    "Polynomial",
    "Spring",
    "TripleFrictionPendulum",
    "ViscousDamper",
]
