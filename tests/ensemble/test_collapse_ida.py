"""Collapse in IDA (issue 37): collapse intensities by bisection on the scale factor against
the analytic dynamic instability of a softening SDOF and against a brute-force scan of the
scale factor; the lognormal fragility fit against scipy.stats."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize
import scipy.stats

import duhamel
from duhamel.ensemble import fit_fragility, ida
from duhamel.records import GroundMotion

# An SDOF of unit mass: an elastic column KE in K, a leaning column P/h = TH (PDelta) and an
# elastic-plastic hinge (Bilinear KB, FY, ALPHA): initial stiffness K0 = KE - TH + KB,
# post-yield KP = KE - TH + ALPHA KB < 0.
KE, TH, KB, FY, ALPHA = 10.0, 8.0, 30.0, 0.3, -0.1
K0, KP = KE - TH + KB, KE - TH + ALPHA * KB
UY = FY / KB
F_Y = K0 * UY


def sdof(motion: GroundMotion, zeta: float = 0.0) -> duhamel.System:
    s = duhamel.System(np.eye(1), [[KE]], zeta=zeta)
    s.add(duhamel.elements.PDelta(0, None, P=TH, height=1.0))
    s.add(duhamel.elements.Bilinear(0, k=KB, fy=FY, alpha=ALPHA))
    return s.add_load(motion.as_load([1.0]))


def damped(motion: GroundMotion) -> duhamel.System:
    return sdof(motion, 0.05)


STOP = duhamel.events.drift(0, None, 20 * UY, height=1.0, terminal=True)


def peak(sol: duhamel.Solution) -> float:
    return float(np.abs(sol.x).max())


def critical_step_force() -> float:
    """The smallest suddenly applied constant force under which the undamped bilinear SDOF
    with a negative post-yield stiffness collapses.

    From rest the mass stops at the first ``u > 0`` where the work ``F u`` equals the strain
    energy ``int_0^u R``. Beyond the point ``u*`` of the descending branch where ``R(u*) = F``
    the net force pushes outward for ever, so the spring collapses when it reaches ``u*``
    with a positive kinetic energy: ``int_0^u* (R - F) du < 0``. With ``a = -K_P / K_0`` and
    ``f = F / F_y``, ``u* = u_y (1 + (1 - f) / a)`` and the energy balance at ``u*`` is
    ``(1 - f)^2 = a (2 f - 1)``: ``f_c = 1 + a - sqrt(a^2 + a)`` (``1/2``, the elastic
    dynamic amplification, for a brittle drop ``a -> inf``; ``1``, the static strength, for
    ``a -> 0``).
    """
    a = -KP / K0
    return F_Y * (1.0 + a - np.sqrt(a * a + a))


def _bracket_of_step(integrator: object, dt: float, tolerance: float) -> np.ndarray:
    fc = critical_step_force()
    step = GroundMotion(np.ones(int(40.0 / dt) + 1), dt, units="m/s^2", name="step")
    res = ida(sdof, [step], [0.5 * fc, 0.9 * fc, 1.1 * fc], peak, integrator, intensity="pga",
              collapse=STOP, solver_error="raise", tolerance=tolerance, workers=1)  # fmt: skip
    # the grid: no collapse at 0.9 fc, a collapse at 1.1 fc
    assert res.measures[0, 1] < 20 * UY and np.isinf(res.measures[0, 2])
    assert not res.failed.any()
    return res.collapse_brackets[0] / fc


@pytest.mark.parametrize("integrator", [duhamel.Semianalytic(), duhamel.Newmark()], ids=str)
def test_collapse_intensity_of_a_step_load_against_the_analytic_instability(
    integrator: object,
) -> None:
    """A constant base acceleration (PGA = the force on the unit mass) from rest: the
    bisected collapse intensity brackets the analytic critical force, to the error of the
    time step, which falls as the step is refined."""
    errors = []
    for dt in (0.02, 0.005, 0.0025):
        lo, hi = _bracket_of_step(integrator, dt, 1e-7)
        assert hi - lo <= 1e-7 * hi
        errors.append(abs(hi - 1.0))
    assert errors[-1] < 1e-5, errors
    assert errors[-1] < errors[0] / 20, errors


def test_collapse_intensity_against_a_brute_force_scan() -> None:
    """A damped SDOF under decaying pulses: the bisection's collapse intensity lies within
    its tolerance of the first collapse of a fine scan of the scale factor (which shows one
    transition inside the coarse bracket)."""
    t = np.arange(0.0, 10.0, 0.01)
    motions = [
        GroundMotion(np.sin(w * t) * np.exp(-0.4 * t), 0.01, units="m/s^2", name=f"w{w:g}")
        for w in (3.0, 5.0, 7.0)
    ]
    grid = [0.2, 0.4, 0.8, 1.6, 3.2]
    res = ida(damped, motions, grid, peak, intensity="pga", collapse=STOP,
              solver_error="raise", tolerance=1e-3, workers=2)  # fmt: skip
    assert res.refinement_runs > 0
    for i, m in enumerate(motions):
        coarse = ida(damped, [m], grid, peak, intensity="pga", collapse=STOP)
        lo0, hi0 = coarse.collapse_brackets[0]
        assert np.isfinite(hi0) and hi0 == coarse.collapse_intensities[0]
        scan = np.linspace(lo0, hi0, 201)[1:]
        fine = ida(damped, [m], scan, peak, intensity="pga", collapse=STOP)
        collapsed = np.isinf(fine.measures[0])
        first = int(np.argmax(collapsed))
        assert collapsed[first] and collapsed[first:].all()  # one transition
        step = scan[1] - scan[0]
        lo, hi = res.collapse_brackets[i]
        assert hi - lo <= 1e-3 * hi and lo0 <= lo < hi <= hi0
        assert scan[first] - step - 1e-12 <= hi <= scan[first] + 1e-3 * hi
        assert res.collapse_intensities[i] == hi


def test_fragility_mle_against_scipy_and_the_true_distribution() -> None:
    """Synthetic collapse intensities from a known lognormal: the MLE equals
    scipy.stats.lognorm.fit (floc=0), and recovers the median and beta within sampling error
    (4 standard errors: beta/sqrt(n) on ln median, beta/sqrt(2n) on beta)."""
    rng = np.random.default_rng(37)
    median, beta, n = 1.7, 0.45, 400
    x = median * np.exp(beta * rng.standard_normal(n))
    frag = fit_fragility(x)
    s, loc, scale = scipy.stats.lognorm.fit(x, floc=0)
    assert loc == 0.0
    assert frag.median == pytest.approx(scale, rel=1e-12)
    assert frag.beta == pytest.approx(s, rel=1e-12)
    assert abs(np.log(frag.median / median)) < 4 * beta / np.sqrt(n)
    assert abs(frag.beta - beta) < 4 * beta / np.sqrt(2 * n)
    mom = fit_fragility(x, "moments")
    assert mom.median == frag.median
    assert mom.beta == pytest.approx(np.std(np.log(x), ddof=1), rel=1e-14)
    p = frag.probability([0.0, frag.median, np.inf])
    assert p.tolist() == [0.0, 0.5, 1.0]
    ref = scipy.stats.lognorm(s, scale=scale).cdf([0.5, 1.0, 3.0])
    np.testing.assert_allclose(frag.probability([0.5, 1.0, 3.0]), ref, rtol=1e-12)


def _tight_fmin(func, x0, args=(), disp=0):
    """scipy's fit with its default Nelder-Mead at tight tolerances (its default stops at
    about 1e-5 of the parameters)."""
    return scipy.optimize.fmin(func, x0, args=args, disp=0, xtol=1e-13, ftol=1e-15,
                               maxiter=100_000, maxfun=100_000)  # fmt: skip


def test_censored_fragility_against_scipy_censored_fit() -> None:
    """A truncated IDA: the records that did not collapse up to the largest intensity are
    right-censored in the likelihood (Baker 2015); the same fit as scipy.stats with
    CensoredData."""
    rng = np.random.default_rng(5)
    x = 2.0 * np.exp(0.5 * rng.standard_normal(60))
    cap = 2.5
    observed = np.where(x > cap, np.inf, x)
    assert 5 < np.isinf(observed).sum() < 40
    frag = fit_fragility(observed, censored_at=cap, mce=0.8)
    data = scipy.stats.CensoredData(
        uncensored=x[x <= cap], right=np.full(int((x > cap).sum()), cap)
    )
    s, _, scale = scipy.stats.lognorm.fit(data, floc=0, optimizer=_tight_fmin)
    assert frag.median == pytest.approx(scale, rel=1e-7)
    assert frag.beta == pytest.approx(s, rel=1e-7)
    assert frag.cmr == frag.median / 0.8
    # ignoring the censored records would bias the median low
    assert fit_fragility(x[x <= cap]).median < frag.median


def test_ida_fragility_and_grid_collapse_intensities() -> None:
    """Without tolerance the collapse intensity is the first collapse on the grid; the IDA's
    fragility is fit_fragility on it with the survivors censored at the largest intensity."""
    t = np.arange(0.0, 10.0, 0.01)
    motions = [
        GroundMotion(np.sin(w * t) * np.exp(-0.4 * t), 0.01, units="m/s^2", name=f"w{w:g}")
        for w in (3.0, 4.0, 5.0, 6.0, 7.0)
    ]
    grid = np.array([0.1, 0.2, 0.4, 0.8, 1.6])
    res = ida(damped, motions, grid, peak, intensity="pga", collapse=STOP)
    for i, row in enumerate(res.measures):
        hits = np.flatnonzero(np.isinf(row))
        expected = grid[hits[0]] if hits.size else np.inf
        assert res.collapse_intensities[i] == expected
    frag = res.fragility(mce=0.3)
    ref = fit_fragility(res.collapse_intensities, censored_at=1.6, mce=0.3)
    assert (frag.median, frag.beta) == (ref.median, ref.beta)


def test_collapse_errors() -> None:
    fc = critical_step_force()
    step = GroundMotion(np.ones(201), 0.02, units="m/s^2", name="step")
    with pytest.raises(ValueError, match="`tolerance`"):
        ida(sdof, [step], [fc], peak, intensity="pga", collapse=STOP, tolerance=1.5)
    with pytest.raises(ValueError, match="no collapse criterion"):
        ida(sdof, [step], [fc], peak, intensity="pga", solver_error="raise", tolerance=0.01)
    with pytest.raises(ValueError, match="`solver_error`"):
        ida(sdof, [step], [fc], peak, intensity="pga", solver_error="ignore")
    with pytest.raises(ValueError, match="`measure` returned nan"):
        ida(sdof, [step], [fc], lambda sol: np.nan, intensity="pga", collapse=STOP)
    with pytest.raises(ValueError, match="`censored_at`"):
        fit_fragility([1.0, 2.0, np.inf])
    with pytest.raises(ValueError, match="moments"):
        fit_fragility([1.0, 2.0, np.inf], "moments", censored_at=3.0)
    with pytest.raises(ValueError, match="above `censored_at`"):
        fit_fragility([1.0, 4.0], censored_at=3.0)
    with pytest.raises(ValueError, match="two different"):
        fit_fragility([1.0, 1.0])
    with pytest.raises(ValueError, match="positive"):
        fit_fragility([1.0, -2.0])
    with pytest.raises(ValueError, match="`method`"):
        fit_fragility([1.0, 2.0], "lsq")
    with pytest.raises(ValueError, match="`mce`"):
        _ = fit_fragility([1.0, 2.0]).cmr


def test_solver_error_is_a_collapse_only_when_stated() -> None:
    """A run that stops with SolverError: a collapse (marked in `failed`) by default, raised
    with a note naming the record with solver_error='raise'."""
    t = np.arange(0.0, 10.0, 0.01)
    motion = GroundMotion(np.sin(5 * t), 0.01, units="m/s^2", name="blows-up")

    def unstable(m: GroundMotion) -> duhamel.System:  # negative damping: it diverges
        s = duhamel.System(np.eye(1), np.eye(1), C=-300.0 * np.eye(1))
        return s.add_load(m.as_load([1.0]))

    res = ida(unstable, [motion], [1.0, 2.0], peak, intensity="pga")
    assert res.failed.all() and np.isinf(res.measures).all()
    assert res.collapse_intensities[0] == 1.0
    with pytest.raises(ValueError, match="collapses at every intensity"):
        ida(unstable, [motion], [1.0], peak, intensity="pga", tolerance=0.1, workers=1)
    with pytest.raises(duhamel.SolverError) as err:
        ida(unstable, [motion], [1.0], peak, intensity="pga",
            solver_error="raise")  # fmt: skip
    assert "solver_error='collapse'" in "".join(err.value.__notes__)
