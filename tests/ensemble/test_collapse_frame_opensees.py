"""Collapse intensities of the 3-storey hinged frame of examples/collapse_ida.py against
OpenSees (issue 37's acceptance: on a frame, the same model, collapse criterion and intensity
steps; each record's collapse intensity within one intensity step; the fragility fit checked
against ``scipy.stats``).

The models, damping (Rayleigh 3 % on the mass and the initial stiffness, the same constant
matrix in both: OpenSees' ``betaKinit``), records, grid and criterion (10 % storey drift or no
convergence): tests/_support/_collapse_frame.py. Five of the example's records (those that collapse
below 2.5 g, to keep the run short), the example's grid of 12 Sa(T1) intensities from 0.25 g
to 3 g (step 0.25 g). OpenSees hunts up the grid to the first collapse, then bisects that
bracket on the intensity to 1 %; duhamel's ``ida`` does the same with ``tolerance=0.01``, with
``Semianalytic()`` and with ``Newmark()``. That the two models are the same is also checked
on one deteriorating transient, and OpenSees' failed steps are checked to count as collapses.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import scipy.stats

import duhamel
from duhamel.ensemble import fit_fragility, ida

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

import _collapse_frame as cf

# At the records' step (0.01 s, the step OpenSees runs) Semianalytic's error bound at the
# hinges is 0.5-2.2 % of their peaks; the true errors against dt/8 are 0.37-0.67 % (record
# syn09 at 1.25 g): the comparison is at this step on purpose, the warning is expected.
pytestmark = pytest.mark.filterwarnings("ignore::duhamel.errors.AccuracyWarning")
RECORDS = (1, 2, 4, 6, 9)  # of the example's 11
TOLERANCE = 0.01
STEP = cf.GRID[1] - cf.GRID[0]


def opensees_ida(motions: list) -> tuple[np.ndarray, np.ndarray, list]:
    """Per record: the first collapse on the grid, that bracket bisected to TOLERANCE (its
    upper end), and the outcomes of the runs."""
    grid = np.full(len(motions), np.inf)
    fine = np.full(len(motions), np.inf)
    log = []
    for i, m in enumerate(motions):
        grid[i], runs = cf.opensees_first_collapse(ops, m, cf.GRID)
        log.append(runs)
        if not np.isfinite(grid[i]):
            continue
        lo, hi, unit = (runs[-2][0] if len(runs) > 1 else 0.0), grid[i], cf.sa1(m)
        while hi - lo > TOLERANCE * hi:
            mid = 0.5 * (lo + hi)
            kind, value = cf.opensees_run(ops, m.scaled(mid / unit).a, m.dt)
            log[-1].append((float(mid), kind, value))
            lo, hi = (lo, mid) if kind != "none" else (mid, hi)
        fine[i] = hi
    ops.wipe()
    return grid, fine, log


@functools.cache
def duhamel_ida(integrator: str) -> object:
    """duhamel's IDA of the same records, grid and criterion, bisected to TOLERANCE."""
    motions = cf.records(max(RECORDS) + 1)
    scheme = duhamel.Newmark() if integrator == "newmark" else duhamel.Semianalytic()
    return ida(cf.frame, [motions[i] for i in RECORDS], cf.GRID, cf.ex.peak_drift_ratio,
               scheme, period=cf.T1, damping=0.05, collapse=cf.ex.collapse_event(),
               solver_error="collapse", workers=2, tolerance=TOLERANCE)  # fmt: skip


@pytest.fixture(scope="module")
def opensees_result() -> tuple[np.ndarray, np.ndarray, list]:
    motions = cf.records(max(RECORDS) + 1)
    return opensees_ida([motions[i] for i in RECORDS])


@pytest.mark.parametrize("integrator", ["semianalytic", "newmark"])
def test_frame_collapse_intensities_equal_opensees(integrator: str, opensees_result) -> None:
    """Each record's first collapse on the grid is within one intensity step of OpenSees'
    (it is the same intensity); bisected to 1 %, within 1 % of OpenSees'. No run of either
    program failed to converge here: every collapse is the drift limit."""
    theirs, theirs_fine, log = opensees_result
    res = duhamel_ida(integrator)
    hit = ~np.isfinite(res.measures)
    ours = np.array([cf.GRID[row.argmax()] if row.any() else np.inf for row in hit])
    print(integrator, "first collapse on the grid [g]: duhamel", ours / cf.G,
          "OpenSees", theirs / cf.G)  # fmt: skip
    print("bisected to 1 % [g]: duhamel", res.collapse_intensities / cf.G, "OpenSees",
          theirs_fine / cf.G)  # fmt: skip
    print("OpenSees outcomes:", [[(round(im / cf.G, 4), k) for im, k, _ in r] for r in log])
    assert np.all(np.isfinite(theirs)), theirs  # every record collapses on the grid
    assert np.all(np.abs(ours - theirs) <= STEP * (1 + 1e-12))
    assert not res.failed.any()
    assert {k for r in log for _, k, _ in r} <= {"none", "drift"}
    np.testing.assert_allclose(res.collapse_intensities, theirs_fine, rtol=TOLERANCE)


def test_frame_fragility_against_scipy(opensees_result) -> None:
    """``fit_fragility`` (maximum likelihood, every record collapsed: no censoring) on the
    OpenSees and the duhamel collapse intensities equals ``scipy.stats.lognorm.fit`` with
    ``floc=0`` on the same intensities (median = scale, beta = shape), and the two programs'
    fragilities agree as their intensities do."""
    _, theirs_fine, _ = opensees_result
    res = duhamel_ida("semianalytic")
    fits = {}
    for name, x in {"OpenSees": theirs_fine, "duhamel": res.collapse_intensities}.items():
        frag = fit_fragility(x)
        shape, loc, scale = scipy.stats.lognorm.fit(x, floc=0)
        print(f"{name}: fit_fragility median {frag.median / cf.G:.5f} g beta {frag.beta:.5f};"
              f" scipy median {scale / cf.G:.5f} g beta {shape:.5f}")  # fmt: skip
        assert loc == 0.0 and frag.censored_at is None
        assert frag.median == pytest.approx(scale, rel=1e-12)
        assert frag.beta == pytest.approx(shape, rel=1e-12)
        fits[name] = frag
    assert fits["duhamel"].median == pytest.approx(fits["OpenSees"].median, rel=TOLERANCE)
    assert res.fragility().median == fits["duhamel"].median


def test_frame_transient_equals_opensees() -> None:
    """The same frame in both programs: record syn09 at Sa(T1) = 1.25 g (peak storey drift
    9.3 %, past capping and deteriorating, just below the collapse limit), each program at
    1/8 of the record's step (OpenSees on the record interpolated linearly, as duhamel reads
    it): the floors' displacements equal within 0.5 % of their peak (issue 37's transient
    acceptance) at every record instant."""
    motion = cf.records(10)[9]
    scaled = motion.scaled(1.25 * cf.G / cf.sa1(motion))
    sub = 8
    t = scaled.dt * np.arange(scaled.a.size)
    fine = np.interp(scaled.dt / sub * np.arange((t.size - 1) * sub + 1), t, scaled.a)
    theirs = cf.opensees_history(ops, fine, scaled.dt / sub)[::sub]
    ops.wipe()
    sol = duhamel.solve(cf.frame(scaled), duhamel.Semianalytic(), t_end=t[-1],
                        dt=scaled.dt / sub, save_every=sub)  # fmt: skip
    ours = sol.x[: theirs.shape[0]]
    assert ours.shape == theirs.shape
    peak = np.abs(theirs).max()
    diff = np.abs(ours - theirs).max() / peak
    drifts = cf.ex.storey_drifts(ours).max(), cf.ex.storey_drifts(theirs).max()
    print(f"floor displacements: largest difference {diff:.2e} of the peak {peak:.3f} m; "
          f"peak storey drift {drifts[0]:.5f} duhamel, {drifts[1]:.5f} OpenSees")  # fmt: skip
    assert 0.09 < drifts[1] < cf.ex.COLLAPSE_DRIFT
    assert diff <= 5e-3


def test_opensees_nonconvergence_is_a_collapse(monkeypatch: pytest.MonkeyPatch) -> None:
    """A run in which OpenSees finds no equilibrium counts as a collapse in the hunt up the
    grid, as duhamel's ``SolverError`` does with ``solver_error='collapse'``: with one Newton
    iteration per step allowed (the first displacement increment above the tolerance fails
    the step) a step fails, and the first intensity is the collapse."""
    monkeypatch.setattr(cf, "ITERATIONS", 1)
    motion = cf.records(1)[0]
    im, runs = cf.opensees_first_collapse(ops, motion, cf.GRID)
    ops.wipe()
    assert im == cf.GRID[0]
    assert runs[0][1] == "nonconvergence" and 0.0 < runs[0][2] < motion.duration
