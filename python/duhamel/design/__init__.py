"""Design studies of isolated buildings: ASCE 7-22 chapters 16 and 17 (:mod:`.asce7`), the
effective properties of an isolator from its own loop (:func:`effective_properties`), a
building as a study sees it (:class:`Building`), the study itself (:class:`Study`: a suite of
records and the property bounds through :func:`duhamel.ensemble.solve_many`, the peaks a
design needs as a labelled dataset, the code checks) and its report
(:meth:`Study.report`: self-contained HTML and a Markdown twin). docs/design.md.

Examples
--------
>>> from duhamel.design import asce7
>>> round(asce7.damping_coefficient(0.15), 12)
1.35
"""

from __future__ import annotations

from duhamel.design import asce7
from duhamel.design.building import Building
from duhamel.design.checks import Check
from duhamel.design.effective import EffectiveProperties, effective_properties
from duhamel.design.study import Study

__all__ = ["Building", "Check", "EffectiveProperties", "Study", "asce7", "effective_properties"]
