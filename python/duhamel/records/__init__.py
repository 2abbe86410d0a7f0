"""Ground-motion records: reading PEER NGA ``.AT2`` and text files, and the quantities
earthquake engineers read off a record (PGA, PGV, PGD, Arias intensity, significant
duration).

A :class:`GroundMotion` holds the acceleration in m/s^2 at uniform samples ``t = k dt``,
whatever the units of its source (kept in ``units``). Between samples the acceleration is
linear, as everywhere in duhamel (:class:`duhamel.loads.BaseAcceleration`), and every
derived quantity is exact for that piecewise-linear record: velocity and displacement are
its exact integrals, the Arias intensity the exact integral of ``a^2``.

Examples
--------
>>> import numpy as np
>>> from duhamel.records import GroundMotion
>>> gm = GroundMotion(np.sin(np.linspace(0.0, 20.0, 2001)), dt=0.01, units="g", name="demo")
>>> round(gm.pga / 9.80665, 6), gm.duration
(1.0, 20.0)
"""

from __future__ import annotations

from duhamel.records.matching import match
from duhamel.records.motion import UNITS, G, GroundMotion
from duhamel.records.pair import GroundMotionPair
from duhamel.records.readers import read_at2, read_text
from duhamel.records.scaling import CriterionTable, ScaledSuite, scale_suite
from duhamel.records.suite import Suite

__all__ = [
    "UNITS",
    "CriterionTable",
    "G",
    "GroundMotion",
    "GroundMotionPair",
    "ScaledSuite",
    "Suite",
    "match",
    "read_at2",
    "read_text",
    "scale_suite",
]
