"""A journal bearing in a run-up alongside ROSS's speed-dependent bearings (issue 40): the
journal swapped in at a bearing whose coefficients follow the speed (its table element
cancelled), against duhamel.rotor's own model of the same rotor — the other bearing as a
table of ROSS's interpolants, the journal — on the same run-up; the two splits of the same
model (which linear part the background carries) converge together as the step falls.
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings

import numpy as np
import pytest

import duhamel
from duhamel.rotor import (
    Bearing,
    Disk,
    Gravity,
    Material,
    Rotor,
    Shaft,
    ShortJournalBearing,
    from_ross,
)
from duhamel.rotor.ross.runup import TABLE_POINTS

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


def frequency_dependent():
    """Three of ROSS's example shaft elements, a disk, two bearings whose coefficients ROSS
    tabulates against frequency (as tests/rotor/test_ross.py's)."""
    ross = _ross()
    base = ross.rotor_example()
    freq = [0.0, 200.0, 400.0, 600.0, 800.0, 1000.0]
    ramp = np.linspace(0.0, 1.0, 6)
    bearings = [
        ross.BearingElement(
            n, kxx=list(1e6 * (1 + 2 * ramp)), kyy=list(0.8e6 * (1 + 2.5 * ramp**2)),
            kxy=list(3e5 * ramp), kyx=list(-3e5 * ramp), cxx=list(500 + 300 * ramp),
            cyy=list(400 + 300 * ramp), frequency=freq,
        )
        for n in (0, 3)
    ]  # fmt: skip
    return ross.Rotor(base.shaft_elements[:3], base.disk_elements[:1], bearings)


def test_a_journal_swapped_in_at_a_speed_dependent_bearing_in_a_run_up():
    rr = frequency_dependent()
    law = duhamel.speed.LinearRunUp(300.0, 900.0, 0.02)
    journal = ShortJournalBearing(0, 0.05, 0.03, 1e-4, 0.03)
    model = from_ross(rr, law)
    model.swap_bearing(journal)
    # duhamel.rotor's model: the same shafts and disk, the bearing at node 3 as a table of
    # ROSS's interpolants on the samples the run-up takes, the journal at node 0
    sh = rr.shaft_elements[0]
    mat = Material(E=sh.material.E, rho=sh.material.rho, G=sh.material.G_s)
    speeds = np.linspace(300.0, 900.0, TABLE_POINTS)
    b3 = rr.bearing_elements[1]
    table = {n: [float(v) for v in getattr(b3, f"{n}_interpolated")(speeds)]
             for n in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")}  # fmt: skip
    native = Rotor(
        [Shaft(s.L, s.odl, s.idl, material=mat) for s in rr.shaft_elements],
        [Disk(d.n, d.m, d.Ip, d.Id) for d in rr.disk_elements],
        [Bearing(3, speeds=speeds.tolist(), **table), journal],
    )
    x_eq = native.static_equilibrium(300.0)
    weight = Gravity().vector(native)
    for i in np.flatnonzero(weight):
        model.system.add_load(duhamel.loads.Tabulated(int(i), t=[0.0, 1.0], values=[weight[i]] * 2))
    x0 = x_eq.copy()
    x0[native.dof(2, "x")] += 5e-6
    errs = []
    for dt in (4e-5, 2e-5, 1e-5):
        kw = dict(t_end=0.02, dt=dt, x0=x0)
        ours = duhamel.solve(model.system, duhamel.Semianalytic(), **kw).x
        ref = duhamel.solve(native.system(law, [Gravity()]), duhamel.Semianalytic(), **kw).x
        errs.append(float(np.abs(ours - ref).max() / np.abs(ref - x_eq).max()))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    print(f"\njournal in a run-up with a speed-following bearing: {errs}, orders {orders}")
    # as tests/rotor/test_ross.py's journal at constant speed: the two splits converge together
    # (orders 1.3, 1.7 measured: approaching 2 as the step falls)
    assert errs[-1] < 1e-2 and errs[0] > errs[1] > errs[2] and errs[1] / errs[2] > 3.0
