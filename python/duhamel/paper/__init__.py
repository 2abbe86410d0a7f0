"""The examples of Holl, Belyaev and Irschik (1999), reproduced and checked.

One function per example returns its data (a dataclass of numpy arrays and the numbers the
report needs, with a ``claims()`` method comparing them with the paper's statements):

- :func:`fig1`: spectral radius of schemes (a), (b), (c), damping as a pseudo-force;
- :func:`fig2`: eq. 25, scheme (b) against Newmark, both signs of the alpha term;
- :func:`fig3`: Duffing oscillator, error phase planes; :func:`cpu_ratios`: loop time
  against Newmark;
- :func:`fig4`: pendulum with decaying mass;
- :func:`figs5to7`: Figs. 5-7 (exponentially varying mass, eq. 44); :func:`fig8`: its
  convergence for several steps;
- :func:`rotor_orbits`: Figs. 9-13, the nonlinear rotor with variable mass (section 4.4);
  :func:`table1`: its modal reduction (Table 1) and Newmark at the same step.

Every function takes size parameters (grid points, steps, repeats) so that a smaller
version runs fast. :mod:`duhamel.paper.figures` draws the figures and :func:`reproduce`
runs everything and writes ``report.md`` (the ``duhamel reproduce`` command). See
``docs/paper.md``.

Examples
--------
>>> from duhamel.paper import fig3
>>> data = fig3(periods=1)
>>> [c.verdict for c in data.claims()][:2]
['holds', 'does not hold']
"""

from duhamel.paper._common import Claim, fit_order
from duhamel.paper.bessel import BesselData, Fig8Data, fig8, figs5to7
from duhamel.paper.duffing import CpuData, DuffingRun, Fig3Data, cpu_ratios, fig3
from duhamel.paper.pendulum import Fig4Data, fig4
from duhamel.paper.report import NAMES, Reproduction, reproduce
from duhamel.paper.rotor import RotorOrbits, Table1Data, rotor_orbits, table1
from duhamel.paper.stability import Fig1Data, Fig2Data, fig1, fig2

__all__ = [
    "NAMES",
    "BesselData",
    "Claim",
    "CpuData",
    "DuffingRun",
    "Fig1Data",
    "Fig2Data",
    "Fig3Data",
    "Fig4Data",
    "Fig8Data",
    "Reproduction",
    "RotorOrbits",
    "Table1Data",
    "cpu_ratios",
    "fig1",
    "fig2",
    "fig3",
    "fig4",
    "fig8",
    "figs5to7",
    "fit_order",
    "reproduce",
    "rotor_orbits",
    "table1",
]
