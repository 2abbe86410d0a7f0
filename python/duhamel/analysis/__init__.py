"""Stability and accuracy analysis of time integrators (the paper's section 3).

Every measure starts from the **amplification matrix** of a linear system, the matrix that
maps the state ``(x, v)`` at ``t`` to ``t + dt``. It is found by stepping the ``2 n`` unit
states once with :func:`duhamel.solve`, so the same tools analyse any integrator the solver
accepts, including the semi-analytic schemes with damping or couplings moved to the
right-hand side as pseudo-forces; :class:`ClosedFormNewmark` is a closed-form reference.

- :func:`amplification_matrix`, :func:`amplification_eigenvalues` (also for integrators
  that carry their own acceleration, by a minimal realization), :func:`spectral_radius`,
  :func:`exact_transition_matrix`, :func:`newmark_amplification`;
- :func:`modal_errors`, :func:`period_error`, :func:`damping_error` (from ``s = ln(lambda)/dt``);
- :func:`local_truncation_error` (Hughes' ``tau``, 1 dof), :func:`one_step_error`,
  :func:`convergence_order` with :class:`ReferenceProblem`;
- :func:`stability_chart`, :func:`plot_stability_chart`, :func:`model_oscillator` (the
  paper's Figs. 1 and 2).

See ``docs/analysis.md`` for the definitions and the reproduced figures.

Examples
--------
>>> import numpy as np, duhamel
>>> from duhamel import analysis
>>> oscillator = analysis.model_oscillator(omega=1.0, zeta=0.1)   # damping as pseudo-force
>>> dt = 0.95 * 2 * np.pi                                         # dt/T = 0.95
>>> [round(analysis.spectral_radius(oscillator, duhamel.Semianalytic(scheme=s), dt), 4)
...  for s in "abc"]
[1.0314, 0.9984, 1.1595]
"""

from duhamel.analysis.accuracy import (
    Convergence,
    ModalErrors,
    ReferenceProblem,
    convergence_order,
    damping_error,
    local_truncation_error,
    modal_errors,
    one_step_error,
    period_error,
)
from duhamel.analysis.chart import (
    StabilityChart,
    model_oscillator,
    plot_stability_chart,
    stability_chart,
)
from duhamel.analysis.matrices import (
    ClosedFormNewmark,
    amplification_eigenvalues,
    amplification_matrix,
    exact_transition_matrix,
    newmark_amplification,
    spectral_radius,
)

__all__ = [
    "ClosedFormNewmark",
    "Convergence",
    "ModalErrors",
    "ReferenceProblem",
    "StabilityChart",
    "amplification_eigenvalues",
    "amplification_matrix",
    "convergence_order",
    "damping_error",
    "exact_transition_matrix",
    "local_truncation_error",
    "modal_errors",
    "model_oscillator",
    "newmark_amplification",
    "one_step_error",
    "period_error",
    "plot_stability_chart",
    "spectral_radius",
    "stability_chart",
]
