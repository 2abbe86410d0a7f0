"""Issue 15, speed-dependent bearings: PCHIP (default) or linear interpolation of the
tables, end values held outside with a TableRangeWarning; the modal analysis and the
unbalance response use each speed's coefficients."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
from duhamel.rotor.bearing import TableRangeWarning

SPEEDS = [100.0, 200.0, 400.0, 700.0]
KXX = [1e7, 1.2e7, 4e7, 4.1e7]  # monotone, with a steep middle: linear would kink, a
CXX = [5e3, 4e3, 1e3, 9e2]  # cubic spline overshoot


def test_pchip_is_shape_preserving_and_exact_at_the_table() -> None:
    b = Bearing(0, KXX, KXX, cxx=CXX, cyy=CXX, speeds=SPEEDS)
    assert b.interpolation == "pchip"
    for w, k, c in zip(SPEEDS, KXX, CXX, strict=True):
        assert b.stiffness_at(w)[0, 0] == k and b.damping_at(w)[0, 0] == c
    ws = np.linspace(SPEEDS[0], SPEEDS[-1], 2001)
    k = np.array([b.stiffness_at(w)[0, 0] for w in ws])
    c = np.array([b.damping_at(w)[0, 0] for w in ws])
    assert np.all(np.diff(k) >= 0) and np.all(np.diff(c) <= 0)  # monotone data stay so
    assert k.min() >= KXX[0] and k.max() <= KXX[-1]  # no overshoot
    # continuous first derivative (a kink would show as a jump in the difference quotient)
    d = np.diff(k) / np.diff(ws)
    assert np.abs(np.diff(d)).max() < 0.02 * np.abs(d).max()
    # the linear option is the broken line
    lin = Bearing(0, KXX, KXX, speeds=SPEEDS, interpolation="linear")
    np.testing.assert_allclose([lin.stiffness_at(w)[0, 0] for w in ws], np.interp(ws, SPEEDS, KXX))
    with pytest.raises(ValueError, match="`interpolation`"):
        Bearing(0, KXX, KXX, speeds=SPEEDS, interpolation="cubic")


def test_outside_the_table_the_end_values_are_held_with_a_warning() -> None:
    b = Bearing(2, KXX, 1e7, speeds=SPEEDS)
    with pytest.warns(TableRangeWarning, match=r"node 2 .* 1000 rad/s, outside its table"):
        assert b.stiffness_at(1000.0)[0, 0] == KXX[-1]
    with pytest.warns(TableRangeWarning):
        assert b.stiffness_at(0.0)[0, 0] == KXX[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b.stiffness_at(150.0)  # inside: no warning
        Bearing(2, 1e7, 1e7).stiffness_at(1e5)  # constant coefficients: no table, no warning


def test_modes_and_unbalance_response_follow_the_table() -> None:
    def rotor(bearing):
        shafts = [Shaft(0.25, 0.05, material=STEEL)] * 4
        return Rotor(shafts, [Disk(2, 30.0, 0.6, 0.3)],
                     [bearing(0), bearing(4)], rayleigh=(0.0, 1e-5))  # fmt: skip

    tab = rotor(lambda n: Bearing(n, KXX, KXX, cxx=CXX, cyy=CXX, speeds=SPEEDS))
    ws = np.array([150.0, 330.0, 650.0])
    res = tab.unbalance_response(ws, [(2, 1e-4, 0.0)])
    for i, w in enumerate(ws):
        k, c = tab.bearings[0].stiffness_at(w)[0, 0], tab.bearings[0].damping_at(w)[0, 0]
        held = rotor(lambda n, k=k, c=c: Bearing(n, k, k, cxx=c, cyy=c))
        np.testing.assert_array_equal(tab.natural_frequencies(w), held.natural_frequencies(w))
        ref = held.unbalance_response([w], [(2, 1e-4, 0.0)]).response[0]
        np.testing.assert_allclose(res.response[i], ref, rtol=1e-13, atol=1e-22)
