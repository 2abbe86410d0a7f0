"""Physical constants, each defined once for the whole library.

:data:`STANDARD_GRAVITY` is the acceleration of 1 g everywhere duhamel converts between g and
m/s^2 or weighs a mass: records read in g (:mod:`duhamel.records`), spectra and targets in g
(:mod:`duhamel.spectra`), the ASCE 7 formulas of :mod:`duhamel.design` (``D = g S_M1 T /
(4 pi^2 B)``, ``T = 2 pi sqrt(W / (k g))``), the seismic weight of a model, a rotor's own
weight (:class:`duhamel.rotor.Gravity`) and the demo. Functions where the value matters take
it as a parameter (``g=``) with this default.

Examples
--------
>>> from duhamel.constants import STANDARD_GRAVITY
>>> STANDARD_GRAVITY
9.80665
"""

from __future__ import annotations

__all__ = ["STANDARD_GRAVITY"]

#: Standard gravity g_n = 9.80665 m/s^2, exact by definition (3rd CGPM, 1901; ISO 80000-3):
#: the value of 1 g in every conversion of the library. A value of 9.81 differs by 3.4e-4
#: relative: enough to move a scaled suite's ratio to its target from 0.9000 to 0.8997.
STANDARD_GRAVITY: float = 9.80665
