"""Regression tests of the rotor items of issue 38 (bad input and silent data loss):

* ``RossDofs.to_ross`` / ``from_ross`` of a complex array kept only its real part (numpy's
  only sign a ``ComplexWarning``): a phase comparison read 87 % off;
* ``level1_stability(q_a=-1e5)`` was accepted (ratio NaN, a verdict from a negative Q_A);
* a Level I curve without a threshold within ``q_range`` gave NaN without a warning;
* ``level1_stability(location=99)`` named ``node`` instead of ``location``;
* ``critical_speed_map(speeds=[])`` raised an ``IndexError``.

(The last item of the list, a heavily damped mode listed as a critical speed, is
tests/rotor/test_rotor_critical_speeds.py.)
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings

import numpy as np
import pytest

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, from_ross
from duhamel.rotor.ross import RossDofs
from duhamel.rotor.stability import ThresholdWarning

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


def rotor(c: float = 1e4) -> Rotor:
    return Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 4,
        [Disk(2, 30.0, 0.6, 0.3)],
        [Bearing(n, 1e7, 1e7, cxx=c, cyy=c) for n in (0, 4)],
    )


# ---------------------------------------------------------------------- complex arrays
def test_to_ross_keeps_complex_values_without_ross():
    dofs = RossDofs(np.array([0, 1, 3, 4]), ("x_0", "y_0", "alpha_0", "beta_0"), 6)
    z = np.array([[1.0 + 2.0j, -3.0j, 0.5, 4.0 - 1.0j]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning: nothing is discarded
        out = dofs.to_ross(z)
        back = dofs.from_ross(out)
    assert out.dtype == np.complex128 and out.shape == (1, 6)
    np.testing.assert_array_equal(out[0, [0, 1, 3, 4]], z[0])
    np.testing.assert_array_equal(out[0, [2, 5]], 0.0)
    np.testing.assert_array_equal(back, z)
    real = dofs.to_ross(np.ones(4))
    assert real.dtype == np.float64  # real arrays stay real


def test_to_ross_of_an_unbalance_response_equals_rosss_complex_response():
    """The phase survives: our unbalance response spread onto ROSS's dofs equals ROSS's own
    complex ``forced_resp`` (real and imaginary parts) on every lateral dof."""
    ross = _ross()
    base = ross.rotor_example()
    bearings = [ross.BearingElement(n, kxx=1e6, kyy=8e5, cxx=800.0, cyy=600.0) for n in (0, 6)]
    rr = ross.Rotor(base.shaft_elements, base.disk_elements, bearings)
    speeds = np.linspace(50.0, 1000.0, 40)
    with contextlib.redirect_stdout(io.StringIO()):
        theirs = rr.run_unbalance_response(2, 1e-3, 0.4, speeds).forced_resp.T
    model = from_ross(rr, 0.0)
    ours = model.dofs.to_ross(model.unbalance_response(speeds, [(2, 1e-3, 0.4)]).response)
    assert ours.dtype == np.complex128
    lateral = model.dofs.ross_index
    err = np.abs(ours[:, lateral] - theirs[:, lateral]).max() / np.abs(theirs).max()
    assert err < 1e-10
    assert np.abs(theirs[:, lateral].imag).max() > 0.1 * np.abs(theirs).max()


# ---------------------------------------------------------------------- Level I
@pytest.mark.parametrize("q_a", [-1e5, 0.0, np.nan, np.inf])
def test_level1_refuses_a_q_a_that_is_not_positive(q_a):
    with pytest.raises(ValueError, match="`q_a`"):
        rotor().level1_stability(600.0, location=2, q_range=[0.0, 1e5], q_a=q_a)


def test_level1_warns_when_no_threshold_is_in_range():
    with pytest.warns(ThresholdWarning, match="q_range"):
        res = rotor().level1_stability(600.0, location=2, q_range=[0.0, 1e3, 2e3])
    assert np.isnan(res.threshold) and res.log_dec[-1] > 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", ThresholdWarning)  # a threshold in range: silent
        found = rotor().level1_stability(600.0, location=2, q_range=np.linspace(0, 4e5, 9))
    assert found.log_dec[0] > 0.0 > found.log_dec[-1] and np.isfinite(found.threshold)


@pytest.mark.parametrize("location", [99, [2, 99], -1])
def test_level1_names_location_for_a_node_that_does_not_exist(location):
    with pytest.raises(ValueError, match="`location`") as info:
        rotor().level1_stability(600.0, location=location)
    assert "`node`" not in str(info.value)


def test_level1_names_location_on_a_ross_model():
    model = from_ross(_ross().rotor_example(), 0.0)
    with pytest.raises(ValueError, match="`location`"):
        model.rotor.level1_stability(500.0, location=99)
    with pytest.raises(TypeError, match="`location`"):
        model.rotor.level1_stability(500.0, location=[2.5])


# ---------------------------------------------------------------------- critical speed map
@pytest.mark.parametrize("speeds", [[], [100.0], [0.0, 0.0], [500.0, 100.0], [-1.0, 10.0]])
def test_critical_speed_map_refuses_speeds_without_a_range(speeds):
    with pytest.raises(ValueError, match="`speeds`"):
        rotor().critical_speed_map(np.logspace(6, 8, 5), n_modes=1, speeds=speeds)
