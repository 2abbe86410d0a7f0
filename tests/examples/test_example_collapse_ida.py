"""examples/collapse_ida.py on a small record set: the storey hinge is the ModIMK hinge the
example states (its closed-form backbone, deterioration under cycles), every record's
collapse intensity is bisected to the tolerance, and the fragility is the fit of those
intensities."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import duhamel
from duhamel.ensemble import fit_fragility

ROOT = Path(__file__).resolve().parents[2]


def _example():
    spec = importlib.util.spec_from_file_location(
        "collapse_ex", ROOT / "examples" / "collapse_ida.py"
    )
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    return ex


def imk_backbone(u: np.ndarray, k0: float, my: float, a_s: float, theta_p: float,
                 theta_pc: float, res: float, theta_u: float) -> np.ndarray:  # fmt: skip
    """The monotonic backbone of ModIMKPeakOriented (n = 0; Lignos & Krawinkler 2011, fig. 1,
    docs/materials.md), in closed form: elastic to My, hardening ``a_s k0`` to the cap at
    ``dy + theta_p``, the post-capping line through zero force ``theta_pc`` after the cap,
    the residual plateau ``res My``, zero from ``theta_u``."""
    dy = my / k0
    uc = dy + theta_p
    fc = my + a_s * k0 * theta_p
    f = np.where(u <= dy, k0 * u, my + a_s * k0 * (u - dy))
    f = np.where(u > uc, np.maximum(fc * (1.0 - (u - uc) / theta_pc), res * my), f)
    return np.where(u >= theta_u, 0.0, f)


def test_storey_backbone_of_the_example() -> None:
    """Each storey's hinge pushed monotonically is the ModIMK closed-form backbone with the
    parameters the example states (yield at 1 % drift, Mc/My, theta_p, theta_pc, residual,
    theta_u as drift ratios); with its elastic column and leaning column the storey's
    post-capping stiffness is negative, and its strength is still positive at the collapse
    drift (the collapse is dynamic, by the drift limit)."""
    ex = _example()
    s = ex.frame()
    drift = np.linspace(0.0, 1.5 * ex.THETA_U, 6001)
    u = drift * ex.H
    for storey, (k, p) in enumerate(zip(ex.K_STOREY, ex.leaning_load(), strict=True)):
        (hinge,) = [e for e in s.elements if e.i == storey]
        assert isinstance(hinge, duhamel.elements.ModIMKPeakOriented)
        force = duhamel.elements.drive(hinge, u).force
        k0, my = ex.HINGE * k, ex.HINGE * k * ex.YIELD_DRIFT * ex.H
        a_s = (ex.CAPPING - 1.0) * ex.YIELD_DRIFT / ex.THETA_P
        ref = imk_backbone(u, k0, my, a_s, ex.THETA_P * ex.H, ex.THETA_PC * ex.H,
                           ex.RESIDUAL, ex.THETA_U * ex.H)  # fmt: skip
        away = np.abs(drift - ex.THETA_U) > 1e-9  # the fracture point itself
        np.testing.assert_allclose(force[away], ref[away], rtol=0, atol=1e-9 * my)
        np.testing.assert_allclose(force.max(), ex.CAPPING * my, rtol=1e-12)
        storey_force = force + (ex.LINEAR * k - p / ex.H) * u
        # post-capping storey stiffness: the hinge's, the column's, the leaning column's
        post = -ex.CAPPING * my / (ex.THETA_PC * ex.H) + ex.LINEAR * k - p / ex.H
        if storey == 0:  # the first storey softens (the upper ones stay near zero)
            assert post < -0.01 * k
        cap = ex.YIELD_DRIFT + ex.THETA_P
        on = (drift > 1.01 * cap) & (force > 1.01 * ex.RESIDUAL * my)
        assert on.sum() > 100
        np.testing.assert_allclose(np.gradient(storey_force, u)[on][1:-1], post,
                                   rtol=0, atol=1e-6 * k)  # fmt: skip
        assert np.all(storey_force[(drift > 0) & (drift <= ex.COLLAPSE_DRIFT)] > 0)


def test_hinge_deteriorates_under_cycles() -> None:
    """Constant-amplitude cycles at 2 % drift (before the cap): without cyclic deterioration
    every cycle would reach the same peak force; with Lambda each peak is lower than the one
    before, and the first cycle's peak is the hardening backbone's."""
    ex = _example()
    hinge = ex.hinge(0, None, ex.K_STOREY[0])
    amp = 0.02 * ex.H
    one = np.r_[np.linspace(0, amp, 50), np.linspace(amp, -amp, 100)[1:],
                np.linspace(-amp, 0, 50)[1:]]  # fmt: skip
    h = duhamel.elements.drive(hinge, np.tile(one, 6))
    peaks = h.force.reshape(6, -1).max(axis=1)
    k0, my = ex.HINGE * ex.K_STOREY[0], ex.HINGE * ex.K_STOREY[0] * ex.YIELD_DRIFT * ex.H
    a_s = (ex.CAPPING - 1.0) * ex.YIELD_DRIFT / ex.THETA_P
    assert peaks[0] == pytest.approx(my + a_s * k0 * (amp - my / k0), rel=1e-12)
    assert np.all(np.diff(peaks) < 0)


def test_collapse_ida_example(tmp_path: Path) -> None:
    ex = _example()
    png = tmp_path / "collapse_ida.png"
    out = ex.main(["--records", "3", "--steps", "6", "--tolerance", "0.05", "--save", str(png)])
    res, frag = out["ida"], out["fragility"]
    assert png.stat().st_size > 10_000
    assert res.measures.shape == (3, 6) and not res.failed.any()
    lo, hi = res.collapse_brackets.T
    assert np.all(np.isfinite(hi)) and np.all(hi - lo <= 0.05 * hi)
    assert np.all(hi <= res.intensities[-1]) and res.refinement_runs > 0
    # below the collapse intensity every run stays below the collapse drift
    below = res.intensities[None, :] <= lo[:, None]
    assert np.all(res.measures[below] < ex.COLLAPSE_DRIFT)
    assert np.all(res.collapse_measures < ex.COLLAPSE_DRIFT)
    ref = fit_fragility(hi, mce=out["s_mt"])
    assert (frag.median, frag.beta) == (ref.median, ref.beta)
    assert frag.cmr == pytest.approx(frag.median / out["s_mt"], rel=1e-15)
