"""Response spectra of ground motions, exact for records linear between their samples.

Each oscillator ``x'' + 2 zeta omega x' + omega^2 x = -a_g(t)`` is stepped with its exact
transition and load-transfer matrices (the Nigam-Jennings method, which is duhamel's method
for one oscillator): no sub-stepping, no error from ``omega dt`` however small or large. The
loops run in Rust, in parallel over records x dampings x periods, several oscillators per pass
over a record. Peaks are taken at the record's samples.

* :func:`response_spectrum`: ``sd``, ``sv`` (relative), ``sa`` (absolute acceleration),
  ``psv = omega sd`` and ``psa = omega^2 sd``;
* :func:`rotd`: RotD50/RotD100 (Boore 2010) of two horizontal components;
* :func:`ductility_spectrum`: constant-ductility inelastic spectra of the bilinear
  oscillator (the yield strength found per period);
* :class:`TargetSpectrum`, :func:`asce7`, :func:`asce7_multi_period`, :func:`eurocode8`:
  design (target) spectra.

Examples
--------
>>> import numpy as np
>>> from duhamel.records import GroundMotion
>>> from duhamel.spectra import response_spectrum
>>> t = np.arange(0.0, 20.0, 0.01)
>>> gm = GroundMotion(0.3 * np.sin(2 * np.pi * t) * np.exp(-0.2 * t), dt=0.01, units="g")
>>> rs = response_spectrum(gm, periods=[0.0, 0.5, 1.0, 2.0], damping=[0.02, 0.05])
>>> rs.psa.shape  # (motions, dampings, periods)
(1, 2, 4)
>>> bool(rs.sa[0, 0, 2] > rs.sa[0, 1, 2] > gm.pga)  # resonance at 1 s, less with damping
True
"""

from __future__ import annotations

from duhamel.spectra.response import (
    DuctilitySpectrum,
    ResponseSpectrum,
    RotDSpectrum,
    ductility_spectrum,
    response_spectrum,
    rotd,
)
from duhamel.spectra.target import TargetSpectrum, asce7, asce7_multi_period, eurocode8

__all__ = [
    "DuctilitySpectrum",
    "ResponseSpectrum",
    "RotDSpectrum",
    "TargetSpectrum",
    "asce7",
    "asce7_multi_period",
    "ductility_spectrum",
    "eurocode8",
    "response_spectrum",
    "rotd",
]
