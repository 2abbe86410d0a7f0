"""ASCE 7-22 chapters 16 and 17 for isolated structures: the equations of the equivalent
lateral force procedure (:mod:`.equations`, section 17.5), the procedure itself with bounds
on the isolator properties (:func:`isolated_elf`, :mod:`.elf`), and the response-history
provisions (:mod:`.history`: suite statistics of section 17.6.3.4, lower limits of section
17.6.4, drift acceptance of sections 17.6.4.4 and 16.4.1.2 with Table 12.12-1).

Units: spectral values in g, lengths in m, forces in N, damping ratios as fractions (like
``zeta``), gravity :data:`duhamel.constants.STANDARD_GRAVITY` (a ``g=`` parameter where it
enters). Each function cites its section and equation.

Examples
--------
>>> from duhamel.design import asce7
>>> asce7.damping_coefficient(0.25)
1.6
>>> round(asce7.isolation_displacement(sm1=0.9, period=2.8, beta=0.17), 4)
0.444
"""

from __future__ import annotations

from duhamel.design.asce7.elf import ELFBound, IsolatedELF, isolated_elf
from duhamel.design.asce7.equations import (
    TABLE_17_5_1,
    base_shear,
    damping_coefficient,
    effective_period,
    isolation_displacement,
    structure_shear,
    torsion_period_ratio,
    total_displacement,
    unreduced_shear,
    vertical_distribution,
)
from duhamel.design.asce7.history import (
    MIN_RECORDS,
    TABLE_12_12_1,
    allowable_drift,
    drift_acceptance,
    isolated_drift_check,
    lower_limit_checks,
    suite_value,
)
from duhamel.design.effective import EffectiveProperties, effective_properties

__all__ = [
    "MIN_RECORDS",
    "TABLE_12_12_1",
    "TABLE_17_5_1",
    "ELFBound",
    "EffectiveProperties",
    "IsolatedELF",
    "allowable_drift",
    "base_shear",
    "damping_coefficient",
    "drift_acceptance",
    "effective_period",
    "effective_properties",
    "isolated_drift_check",
    "isolated_elf",
    "isolation_displacement",
    "lower_limit_checks",
    "structure_shear",
    "suite_value",
    "torsion_period_ratio",
    "total_displacement",
    "unreduced_shear",
    "vertical_distribution",
]
