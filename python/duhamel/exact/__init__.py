"""Exact reference solutions for verifying time integrators.

Each function evaluates a closed-form (or matrix-exponential) solution at the given times,
so that any integrator, in this package or elsewhere, can be checked against it to
round-off. The nonlinear and time-varying cases are the examples of Holl, Belyaev and
Irschik (1999), sections 4.1 to 4.3:

- :func:`duffing`: free vibration of the undamped Duffing oscillator (Jacobi ``cn``).
- :func:`duffing_period`: its period.
- :func:`decaying_mass_pendulum`: linearised pendulum whose mass decays exponentially,
  under a step load (the paper's eq. 31, with its sine coefficient corrected).
- :func:`bessel_mass`: free vibration with mass ``m0 K exp(-2 a omega t)`` (Bessel
  functions of order one, the paper's eq. 44).
- :func:`linear`: any linear time-invariant :class:`~duhamel.System` under a polynomial or
  harmonic load, by the matrix exponential of an augmented first-order system.

All times are measured from the initial instant ``t = 0`` and must be non-negative. Each
family lives in its own module: :mod:`~duhamel.exact.nonlinear` (Duffing),
:mod:`~duhamel.exact.varying_mass` (sections 4.2, 4.3), :mod:`~duhamel.exact.lti`.
"""

from duhamel.exact.lti import linear
from duhamel.exact.nonlinear import duffing, duffing_period
from duhamel.exact.varying_mass import bessel_mass, decaying_mass_pendulum

__all__ = ["bessel_mass", "decaying_mass_pendulum", "duffing", "duffing_period", "linear"]
