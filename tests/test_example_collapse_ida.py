"""examples/collapse_ida.py on a small record set: the storey backbone is the one the
example states, every record's collapse intensity is bisected to the tolerance, and the
fragility is the fit of those intensities."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import duhamel
from duhamel.ensemble import fit_fragility

ROOT = Path(__file__).resolve().parents[1]


def _example():
    spec = importlib.util.spec_from_file_location(
        "collapse_ex", ROOT / "examples" / "collapse_ida.py"
    )
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    return ex


def test_storey_backbone_of_the_example() -> None:
    """Each storey pushed monotonically (its elements driven, its elastic column and its
    leaning column added): elastic to 1 % drift, positive hardening to the cap at the stated
    drift, then the stated post-capping stiffness (P-Delta included); the strength is still
    positive at the collapse drift (the collapse is dynamic, by the drift limit)."""
    ex = _example()
    s = ex.frame()
    drift = np.linspace(0.0, 2 * ex.COLLAPSE_DRIFT, 4001)
    u = drift * ex.H
    for storey, (k, p) in enumerate(zip(ex.K_STOREY, ex.leaning_load(), strict=True)):
        hinges = [e for e in s.elements if e.i == storey]
        assert len(hinges) == 2
        force = sum(duhamel.elements.drive(e, u).force for e in hinges)
        force = force + (ex.LINEAR * k - p / ex.H) * u
        slope = np.gradient(force, u)
        elastic, hard = (
            drift < 0.9 * ex.YIELD_DRIFT,
            (drift > 1.1 * ex.YIELD_DRIFT) & (drift < 0.9 * ex.CAP_DRIFT),
        )
        post = drift > 1.1 * ex.CAP_DRIFT
        np.testing.assert_allclose(slope[elastic], k - p / ex.H, rtol=1e-9)
        assert np.all(slope[hard] > 0)
        np.testing.assert_allclose(slope[post], ex.POST_CAP * k, rtol=1e-9)
        assert np.all(force[(drift > 0) & (drift <= ex.COLLAPSE_DRIFT)] > 0)


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
