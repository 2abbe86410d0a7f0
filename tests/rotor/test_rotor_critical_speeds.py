"""Critical speeds as API 684 reports them (issue 40; issue 38's heavily damped "critical
speed"): heavily damped crossings listed apart, each critical speed with its damping, the
amplification factor by the half-power method on the unbalance response and the
separation margins from an operating range.

References: a Jeffcott rotor's unbalance response in closed form (peak at
``omega_n / sqrt(1 - 2 zeta^2)``, half-power speeds the roots of a quadratic in
``Omega^2``), and the unbalance response sampled on a fine grid (``peaks()``).
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings
from typing import ClassVar

import numpy as np
import pytest

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, from_ross
from duhamel.rotor.critical import HEAVY_DAMPING, CriticalSpeeds

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


def jeffcott(m: float, k: float, zeta: float):
    """A rigid disk on isotropic springs (ROSS's interface, 4 dofs at one node; the tilts
    far stiffer), damping ``c = 2 zeta sqrt(k m)`` on x and y."""
    c = 2.0 * zeta * np.sqrt(k * m)

    class Disk:
        dof_global_index: ClassVar = {"x_0": 0, "y_0": 1, "alpha_0": 2, "beta_0": 3}

    class Toy:
        elements = (Disk(),)

        def M(self, f=None):
            return np.diag([m, m, 0.1, 0.1])

        def K(self, f):
            return np.diag([k, k, 1e9, 1e9])

        def C(self, f):
            return np.diag([c, c, 0.0, 0.0])

        def G(self):
            return np.zeros((4, 4))

    return from_ross(Toy(), 0.0).rotor, c


def jeffcott_closed_form(m, k, c, m_e):
    """Peak speed, peak amplitude and half-power speeds of ``m_e W^2 / |k - m W^2 + i c W|``."""
    wn, zeta = np.sqrt(k / m), c / (2.0 * np.sqrt(k * m))
    wp = wn / np.sqrt(1.0 - 2.0 * zeta**2)
    peak = m_e * wp**2 / abs(k - m * wp**2 + 1j * c * wp)
    # peak^2 ((k - m u)^2 + c^2 u) = 2 m_e^2 u^2,  u = W^2
    u = np.roots([peak**2 * m**2 - 2.0 * m_e**2, peak**2 * (c**2 - 2.0 * k * m), peak**2 * k**2])
    n1, n2 = np.sort(np.sqrt(u.real))
    return wp, peak, n1, n2


def required(af: float, below: bool) -> float:
    if af < 2.5:
        return 0.0
    base = 0.17 * (1.0 - 1.0 / (af - 1.5))
    return min(0.16, base) if below else min(0.26, 0.10 + base)


@pytest.mark.parametrize("zeta", [0.01, 0.05, 0.15])
def test_jeffcott_amplification_factor_and_margins_equal_the_closed_form(zeta):
    m, k = 10.0, 1e6
    rotor, c = jeffcott(m, k, zeta)
    wn = np.sqrt(k / m)
    lo, hi = 1.4 * wn, 1.6 * wn
    crit = rotor.critical_speeds(np.linspace(0.0, 2.0 * wn, 21), operating=(lo, hi))
    assert isinstance(crit, CriticalSpeeds) and crit.size == 1 and not crit.heavily_damped
    cs = crit.critical[0]
    # the forward crossing: the damped natural frequency equals the speed
    assert abs(cs.speed - wn * np.sqrt(1.0 - zeta**2)) < 1e-12 * wn
    assert abs(cs.damping_ratio - zeta) < 1e-12 and cs.whirl == "forward" and cs.node == 0
    wp, peak, n1, n2 = jeffcott_closed_form(m, k, c, 1e-4)
    # a maximum is located to about sqrt(eps) of its speed (the curve is flat there): the
    # peak speed, and the AF with it, to 1e-8; the amplitude and half-power speeds closer
    assert abs(cs.peak_speed - wp) < 1e-8 * wp
    assert abs(cs.amplitude - peak) < 1e-12 * peak
    assert abs(cs.half_power[0] - n1) < 1e-11 * wn and abs(cs.half_power[1] - n2) < 1e-11 * wn
    af = wp / (n2 - n1)
    assert abs(cs.amplification_factor - af) < 1e-8 * af
    assert abs(af - 1.0 / (2.0 * zeta)) < 0.2 / (2.0 * zeta)  # API 684's AF ~ 1 / (2 zeta)
    assert abs(cs.margin - (lo - wp) / wp) < 1e-8
    assert cs.required_margin == pytest.approx(required(af, below=True), rel=1e-8)
    assert cs.meets_margin == (cs.margin >= cs.required_margin)
    # above the range: measured from the maximum continuous speed
    above = rotor.critical_speeds([0.0, 2.0 * wn], operating=(0.5 * wn, 0.8 * wn)).critical[0]
    assert abs(above.margin - (wp - 0.8 * wn) / (0.8 * wn)) < 1e-8
    assert above.required_margin == pytest.approx(required(af, below=False), rel=1e-8)
    inside = rotor.critical_speeds([0.0, 2.0 * wn], operating=(0.5 * wn, 1.5 * wn)).critical[0]
    assert inside.margin < 0.0 and not inside.meets_margin


def test_a_heavily_damped_crossing_is_listed_apart():
    m, k = 10.0, 1e6
    rotor, _ = jeffcott(m, k, 0.3)  # AF about 1.7: critically damped in API 684's sense
    crit = rotor.critical_speeds(np.linspace(0.0, 800.0, 17), operating=(500.0, 600.0))
    assert crit.size == 0 and len(crit.heavily_damped) == 1
    heavy = crit.heavily_damped[0]
    assert heavy.heavily_damped and abs(heavy.damping_ratio - 0.3) < 1e-12
    assert heavy.required_margin == 0.0 and heavy.meets_margin
    assert "heavily damped (zeta > 0.2): 301.66 rad/s" in crit.summary()
    kept = rotor.critical_speeds(np.linspace(0.0, 800.0, 17), max_damping=0.5)
    assert kept.size == 1 and kept[0] == heavy.speed
    with pytest.raises(ValueError, match="`max_damping`"):
        rotor.critical_speeds([0.0, 800.0], max_damping=0.0)
    with pytest.raises(ValueError, match="`operating`"):
        rotor.critical_speeds([0.0, 800.0], operating=(600.0, 500.0))


def two_span_rotor() -> Rotor:
    return Rotor(
        [Shaft(0.2, 0.05, material=STEEL)] * 6,
        [Disk(2, 25.0, 0.5, 0.25), Disk(5, 15.0, 0.3, 0.15)],
        [Bearing(n, 2e7, 1.5e7, cxx=3e3, cyy=2e3, kxy=1e5, kyx=-1e5) for n in (0, 6)],
        zeta=0.01,
    )


def test_amplification_factors_equal_the_sampled_unbalance_response():
    """Each critical speed's peak speed, amplitude and AF equal those of the unbalance
    response (same unbalance and node) sampled on a fine grid and read by ``peaks()``, to
    the grid's accuracy."""
    rotor = two_span_rotor()
    crit = rotor.critical_speeds(np.linspace(0.0, 3000.0, 31), operating=(900.0, 1100.0))
    assert crit.size >= 2
    for cs in crit.critical:
        assert cs.damping_ratio <= HEAVY_DAMPING
        half = 10 * cs.damping_ratio * cs.speed
        grid = np.linspace(cs.speed - half, cs.speed + half, 20001)
        res = rotor.unbalance_response(grid, [(cs.node, 1e-4, 0.0)])
        peaks = res.peaks(cs.node, operating=(900.0, 1100.0))
        near = min(peaks, key=lambda p: abs(p.speed - cs.peak_speed))
        step = grid[1] - grid[0]
        assert abs(near.speed - cs.peak_speed) < 0.05 * step
        assert abs(near.amplitude - cs.amplitude) < 1e-6 * cs.amplitude
        for ours, sampled in zip(cs.half_power, near.half_power, strict=True):
            assert abs(ours - sampled) < 1e-3 * step
        assert (
            abs(near.amplification_factor - cs.amplification_factor)
            < 1e-5 * near.amplification_factor
        )
        assert abs(near.margin - cs.margin) < 1e-6 and near.required_margin == pytest.approx(
            cs.required_margin, rel=1e-5
        )
        # the node read is where the mode moves most
        modes = rotor.modes(cs.speed)
        j = int(np.argmin(np.abs(modes.frequencies - cs.speed)))
        amp = np.hypot(np.abs(modes.shapes[0::4, j]), np.abs(modes.shapes[1::4, j]))
        assert cs.node == int(np.argmax(amp))
    # a given unbalance read at a given node
    first = crit.critical[0]
    other = rotor.critical_speeds([0.0, 3000.0], unbalances=[(5, 2e-4, 1.0)], probe=5)
    assert other.critical[0].node == 5 and other.critical[0].speed == pytest.approx(first.speed)


def test_as_an_array_it_is_the_critical_speeds():
    crit = two_span_rotor().critical_speeds(np.linspace(0.0, 3000.0, 31))
    arr = np.asarray(crit)
    assert arr.dtype == np.float64 and arr.shape == (crit.size,) == (len(crit),)
    np.testing.assert_array_equal(arr, crit.speeds)
    assert list(crit) == arr.tolist() and crit[0] == arr[0]
    assert np.all(np.diff(arr) > 0)


def test_compressor_leaves_out_its_heavily_damped_modes():
    """ROSS's compressor: the crossings of modes with log decrement about 20 (backward and
    mixed whirl) are listed apart; the forward critical speed carries its AF, checked
    against the unbalance response sampled finely, and its margin."""
    ross = _ross()
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        model = from_ross(ross.compressor_example(), 0.0)
    crit = model.critical_speeds(np.linspace(0.0, 2000.0, 41), whirl=None, operating=(700, 900))
    heavy = crit.heavily_damped
    assert any(h.log_dec > 15.0 and h.whirl == "mixed" for h in heavy)
    assert all(h.damping_ratio > HEAVY_DAMPING for h in heavy)
    assert all(c.damping_ratio <= HEAVY_DAMPING for c in crit.critical)
    assert not set(crit.speeds) & {h.speed for h in heavy}
    forward = [c for c in crit.critical if c.whirl == "forward"]
    assert forward
    cs = forward[0]
    grid = np.linspace(0.7 * cs.speed, 1.3 * cs.speed, 1601)  # zeta 0.1: N_1, N_2 within
    res = model.rotor.unbalance_response(grid, [(cs.node, 1e-4, 0.0)])
    near = min(res.peaks(cs.node, operating=(700, 900)), key=lambda p: abs(p.speed - cs.speed))
    assert abs(near.amplification_factor - cs.amplification_factor) < 1e-3 * cs.amplification_factor
    assert abs(near.speed - cs.peak_speed) < grid[1] - grid[0]
    assert abs(near.margin - cs.margin) < 1e-4
    peaks = [c.peak_speed for c in crit.critical if np.isfinite(c.peak_speed)]
    assert len(set(peaks)) == len(peaks)  # each peak belongs to one critical speed
    print("\n" + crit.summary())


def test_a_peak_belongs_to_the_nearest_critical_speed():
    """A backward crossing next to a forward one: the forward peak of the unbalance response
    is the forward critical speed's; the backward one gets no amplification factor."""
    rotor = two_span_rotor()
    crit = rotor.critical_speeds(np.linspace(0.0, 3000.0, 31), whirl=None)
    with_peak = [c for c in crit.critical if np.isfinite(c.peak_speed)]
    for c in with_peak:
        others = [o.speed for o in crit.critical if o is not c]
        assert all(abs(c.peak_speed - c.speed) <= abs(c.peak_speed - o) for o in others)
    assert any(c.whirl == "backward" and np.isnan(c.amplification_factor) for c in crit.critical)
    assert len({round(c.peak_speed, 6) for c in with_peak}) == len(with_peak)
