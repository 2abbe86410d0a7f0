"""The undamped critical speed map of a from_ross model against the undamped eigenproblem at
each stiffness, on a ROSS rotor rebuilt by ROSS with its bearings replaced by isotropic
springs (as ROSS's own ``run_ucs`` does: seals left out, no damping), and against
``run_ucs``'s frequencies themselves."""

from __future__ import annotations

import contextlib
import functools
import io
import warnings
from typing import ClassVar

import numpy as np
import pytest
import scipy.linalg

from duhamel.rotor import from_ross

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        return pytest.importorskip("ross", reason=REASON)


@functools.cache
def example(name):
    ross = _ross()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the compressor's file was written by an older ROSS
        return getattr(ross, name)()


def sprung(rr, k):
    """ROSS's rotor with each bearing (not seal) an isotropic undamped spring k."""
    ross = _ross()
    bearings = [ross.BearingElement(b.n, kxx=k, cxx=0.0) for b in rr.bearing_elements
                if not isinstance(b, ross.SealElement)]  # fmt: skip
    with contextlib.redirect_stdout(io.StringIO()):
        return ross.Rotor(rr.shaft_elements, rr.disk_elements, bearings)


def reference(rr, dofs, k, gyroscopic, count, ell):
    """The dense general eigenproblem of ROSS's own matrices of the sprung rotor, each
    eigenvalue refined by two steps of Rayleigh-quotient inverse iteration on the Hermitian
    pencil (the dense solvers alone agree only to about 1e-9 on the compressor on soft
    supports, where K's condition number is 1e9)."""
    other = sprung(rr, k)
    keep = np.ix_(dofs.ross_index, dofs.ross_index)
    M, K, G = other.M(0.0)[keep], other.K(0.0)[keep], other.G()[keep]
    n = M.shape[0]
    if gyroscopic:  # forward synchronous whirl: x = Re(X e^{iwt}) at spin w
        B = M - 1j * G
        lam, vec = scipy.linalg.eig(K, B)
        X, Y, Tx, Ty = (vec[d::4] for d in range(4))
        area = np.sum(-np.imag(np.conj(X) * Y) + ell**2 * np.imag(np.conj(Ty) * Tx), axis=0)
        ok = np.isfinite(lam) & (area > 0)
    else:  # at rest, the x-z plane (x, beta)
        plane = np.sort(np.r_[0:n:4, 3:n:4])
        K, B = K[np.ix_(plane, plane)], M[np.ix_(plane, plane)].astype(complex)
        lam, vec = scipy.linalg.eig(K, B)
        ok = np.isfinite(lam)
    ok &= (lam.real > 0) & (np.abs(lam.imag) < 1e-8 * np.abs(lam))
    lam, vec = lam[ok].real, vec[:, ok]
    order = np.argsort(lam)[:count]
    out = []
    for mu, x in zip(lam[order], vec[:, order].T, strict=True):
        for _ in range(2):
            x = scipy.linalg.solve(K - mu * (1.0 - 1e-10) * B, B @ x)
            x /= np.linalg.norm(x)
            mu = float(np.real(np.conj(x) @ K @ x) / np.real(np.conj(x) @ B @ x))
        out.append(np.sqrt(mu))
    return np.array(out)


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
@pytest.mark.parametrize("name", ["rotor_example", "compressor_example"])
@pytest.mark.parametrize("gyroscopic", [True, False])
def test_map_equals_the_undamped_eigenproblem_at_each_stiffness(name, gyroscopic):
    rr = example(name)
    model = from_ross(rr, 0.0)
    # two decades either side of the bearings (1e6 N/m; the compressor's 2e8 N/m). Far below
    # the compressor's (1e5 N/m) the map and this reference differ by 2.4e-10 and the plain
    # dense solvers by 1.4e-9 among themselves: K's condition number (1e9) limits both.
    ks = np.logspace(5, 9, 9) if name == "rotor_example" else np.logspace(6, 10, 5)
    ucs = model.rotor.critical_speed_map(ks, n_modes=4, gyroscopic=gyroscopic)
    ell = float(np.mean([s.L for s in rr.shaft_elements]))
    worst = 0.0
    for i, k in enumerate(ks):
        ref = reference(rr, model.dofs, k, gyroscopic, 4, ell)
        worst = max(worst, float(np.max(np.abs(ucs.critical_speeds[i] - ref) / ref)))
    print(f"\n{name} critical speed map (gyroscopic={gyroscopic}) vs eigenproblem: {worst:.1e}")
    assert worst < 1e-10
    bearing_nodes = {int(b.n) for b in rr.bearing_elements
                     if not isinstance(b, _ross().SealElement)}  # fmt: skip
    assert {node for node, _, _ in ucs.curves} == bearing_nodes


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_map_equals_ross_run_ucs():
    """ROSS's run_ucs (the rotor at rest, scipy.sparse eigs) gives the same frequencies."""
    rr = example("rotor_example")
    ks = np.logspace(6, 10, 3)
    with contextlib.redirect_stdout(io.StringIO()):
        theirs = rr.run_ucs(stiffness_range=(6, 10), num=3, num_modes=16)
    ucs = from_ross(rr, 0.0).rotor.critical_speed_map(ks, n_modes=4, gyroscopic=False)
    ref = np.asarray(theirs.wn).T  # (n_k, n_modes)
    err = float(np.max(np.abs(ucs.critical_speeds - ref[:, :4]) / ref[:, :4]))
    print(f"\ncritical speed map vs ROSS run_ucs: {err:.1e}")
    assert err < 1e-8


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_intersections_are_critical_speeds_of_the_ross_rotor():
    """Where a bearing's curve (ROSS's interpolant) crosses a line, the rotor on springs of
    that stiffness has a forward synchronous critical speed at exactly that speed."""
    ross = _ross()
    base = ross.rotor_example()
    freq = [0.0, 500.0, 1000.0, 1500.0]
    bearings = [ross.BearingElement(n, kxx=[2e6, 5e6, 1e7, 2e7], kyy=[2e6, 5e6, 1e7, 2e7],
                                    cxx=[0.0] * 4, frequency=freq) for n in (0, 6)]  # fmt: skip
    with contextlib.redirect_stdout(io.StringIO()):
        rr = ross.Rotor(base.shaft_elements, base.disk_elements, bearings)
    model = from_ross(rr, 0.0)
    ucs = model.rotor.critical_speed_map(np.logspace(5, 9, 17), n_modes=2,
                                         speeds=np.linspace(0.0, 1500.0, 151))  # fmt: skip
    assert ucs.intersections
    ell = float(np.mean([s.L for s in rr.shaft_elements]))
    for p in ucs.intersections:
        assert p.stiffness == pytest.approx(float(bearings[0].kxx_interpolated(p.speed)), 1e-14)
        crit = reference(rr, model.dofs, p.stiffness, True, 2, ell)
        assert np.min(np.abs(crit - p.speed)) < 1e-9 * p.speed


def test_refuses_a_model_without_bearings():
    class Toy:
        elements = bearing_elements = ()
        K0 = np.diag([1e6, 1e6, 1e4, 1e4])

        def M(self, f=None):
            return np.diag([2.0, 2.0, 0.1, 0.1])

        def K(self, f):
            return self.K0

        def C(self, f):
            return np.zeros((4, 4))

        def G(self):
            return np.zeros((4, 4))

    Toy.elements = [type("D", (), {"dof_global_index": {"x_0": 0, "y_0": 1, "alpha_0": 2,
                                                         "beta_0": 3}})()]  # fmt: skip
    with pytest.raises(ValueError, match="no bearings"):
        from_ross(Toy(), 0.0).rotor.critical_speed_map([1e6])


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_compressor_map_example():
    """examples/ross_ucs_map.py runs; each of its intersections lies on its bearing's curve."""
    import importlib.util
    from pathlib import Path

    _ross()
    path = Path(__file__).resolve().parents[2] / "examples" / "ross_ucs_map.py"
    spec = importlib.util.spec_from_file_location("ross_ucs_map", path)
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    ucs = ex.run(n_k=9)
    assert len(ucs.intersections) >= 4
    curves = {(node, d): k for node, d, k in ucs.curves}
    for p in ucs.intersections:
        k = np.interp(p.speed, ucs.speeds, curves[(p.node, p.direction)])
        assert p.stiffness == pytest.approx(k, rel=1e-2)  # the curve is drawn piecewise linear


def test_without_gyroscopic_terms_forward_whirl_is_the_planar_mode():
    """G = 0: the map with gyroscopic=True equals the one at rest (it found no forward orbit
    before: a degenerate x/y pair has none)."""

    class Bearing:
        n, frequency = 0, None
        dof_global_index: ClassVar = {"x_0": 0, "y_0": 1, "alpha_0": 2, "beta_0": 3}
        kxx_interpolated = kyy_interpolated = staticmethod(lambda w: 1e6 + 0.0 * w)
        kxy_interpolated = kyx_interpolated = staticmethod(lambda w: 0.0 * w)

    class Toy:
        elements = bearing_elements = (Bearing(),)
        K0 = np.diag([0.0, 0.0, 1e6, 1e6])

        def M(self, f=None):
            return np.diag([2.0, 2.0, 0.1, 0.1])

        def K(self, f):
            return self.K0 + np.diag([1e6, 1e6, 0.0, 0.0])

        def C(self, f):
            return np.zeros((4, 4))

        def G(self):
            return np.zeros((4, 4))

    rotor = from_ross(Toy(), 0.0).rotor
    ks = [2e4, 8e4, 1e6]
    spun = rotor.critical_speed_map(ks, n_modes=2)
    rest = rotor.critical_speed_map(ks, n_modes=2, gyroscopic=False)
    np.testing.assert_array_equal(spun.critical_speeds, rest.critical_speeds)
    np.testing.assert_allclose(spun.critical_speeds[:, 0], np.sqrt(np.array(ks) / 2.0), 1e-14)
