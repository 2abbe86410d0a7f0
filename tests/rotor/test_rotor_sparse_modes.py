"""Large rotors fast (issue 40): the lowest modes by shift-invert Arnoldi on the first-order
pencil (:mod:`duhamel.rotor._sparse_modes`), and the analyses built on them (Campbell
diagram, critical speeds, Level I), give the dense QZ path's results (1e-8); ROSS's matrices
per speed from a constant part plus the bearings' curves equal ROSS's own assembly.

The dense path is forced by raising ``SPARSE_DOFS`` above the model's size.
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings

import numpy as np
import pytest

import duhamel.rotor._sparse_modes as sparse
from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, from_ross

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


def long_rotor(bearings: bool = True) -> Rotor:
    """40 elements (164 dofs), three disks, two damped cross-coupled bearings and a seal."""
    shafts = [Shaft(0.05, 0.06 if 10 <= i < 30 else 0.05, material=STEEL) for i in range(40)]
    disks = [Disk(n, 25.0, 0.5, 0.25) for n in (12, 20, 28)]
    supports = [Bearing(n, 3e7, 2e7, kxy=2e5, kyx=-2e5, cxx=5e4, cyy=4e4) for n in (4, 36)] + [
        Bearing(20, 0.0, 0.0, kxy=5e4, kyx=-5e4, cxx=300.0, cyy=300.0)
    ]
    return Rotor(shafts, disks, supports if bearings else (), zeta=0.01)


@pytest.fixture
def dense(monkeypatch):
    """Run what follows on the dense path."""

    def force():
        monkeypatch.setattr(sparse, "SPARSE_DOFS", 10**9)

    return force


def same_modes(a, b, tol=1e-8):
    assert a.n_modes == b.n_modes
    err = float(np.abs(a.eigenvalues - b.eigenvalues).max() / np.abs(b.eigenvalues).max())
    assert err < tol, err
    # shapes: each is determined to about eps |A| / (its distance to the next eigenvalue);
    # the close pairs of these rotors (a relative gap of 1e-4) leave MAC 1 - 1e-8
    assert np.diag(a.mac(b)).min() > 1.0 - 1e-6
    assert a.whirl == b.whirl
    return err


@pytest.mark.parametrize("speed", [0.0, 800.0, 3000.0])
def test_lowest_modes_equal_the_dense_path(speed, dense):
    rotor = long_rotor()
    assert sparse.sparse_worth(rotor.n_dof, 12)
    fast = rotor.modes(speed, n=12)
    dense()
    same_modes(fast, rotor.modes(speed, n=12))


def test_a_free_rotor_takes_the_dense_path():
    """K singular (rigid-body modes at zero, defective without damping there): no shift
    invert at zero; the dense QZ's modes, the gyroscopic conical whirl at 39 rad/s first."""
    rotor = long_rotor(bearings=False)
    M, K, C, G = rotor.matrices(500.0)
    from duhamel.rotor.modes import oscillatory

    assert sparse.lowest_modes(M, C + 500.0 * G, K, 8, oscillatory) is None
    modes = rotor.modes(500.0, n=8)
    assert modes.n_modes == 8 and 30.0 < modes.frequencies[0] < 50.0


def test_campbell_level1_and_critical_speeds_equal_the_dense_path(dense):
    rotor = long_rotor()
    speeds = np.linspace(0.0, 4000.0, 9)
    fast_c = rotor.campbell(speeds, n_modes=6)
    fast_l = rotor.level1_stability(3000.0, location=20, q_range=np.linspace(0, 4e5, 5))
    fast_k = rotor.critical_speeds(np.linspace(0.0, 4000.0, 21), operating=(2500.0, 3000.0))
    dense()
    slow_c = rotor.campbell(speeds, n_modes=6)
    np.testing.assert_allclose(fast_c.frequencies, slow_c.frequencies, rtol=1e-8)
    np.testing.assert_array_equal(fast_c.whirl, slow_c.whirl)
    slow_l = rotor.level1_stability(3000.0, location=20, q_range=np.linspace(0, 4e5, 5))
    np.testing.assert_allclose(fast_l.log_dec, slow_l.log_dec, rtol=1e-8, atol=1e-10)
    assert np.isfinite(slow_l.threshold)
    assert abs(fast_l.threshold - slow_l.threshold) < 1e-8 * slow_l.threshold
    slow_k = rotor.critical_speeds(np.linspace(0.0, 4000.0, 21), operating=(2500.0, 3000.0))
    assert fast_k.size == slow_k.size >= 1
    np.testing.assert_allclose(fast_k.speeds, slow_k.speeds, rtol=1e-8)
    np.testing.assert_allclose(fast_k.amplification_factors, slow_k.amplification_factors,
                               rtol=1e-6)  # fmt: skip


def test_compressor_modes_and_campbell_equal_the_dense_path(dense):
    ross = _ross()
    model = from_ross(ross.compressor_example(), 0.0)
    fast = [model.rotor.modes(w, n=12) for w in (0.0, 1050.0)]
    camp = model.rotor.campbell(np.linspace(0.0, 1500.0, 4), n_modes=8)
    dense()
    speeds = (0.0, 1050.0)
    errs = [same_modes(f, model.rotor.modes(w, n=12)) for f, w in zip(fast, speeds, strict=True)]
    slow = model.rotor.campbell(np.linspace(0.0, 1500.0, 4), n_modes=8)
    np.testing.assert_allclose(camp.frequencies, slow.frequencies, rtol=1e-8)
    print(f"\ncompressor: lowest 12 modes, shift-invert vs QZ {max(errs):.1e}")


def test_rosss_matrices_from_their_split_equal_rosss_assembly():
    ross = _ross()
    for example in (ross.compressor_example, ross.rotor_amb_example):
        with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
            warnings.simplefilter("ignore")
            rr = example()
        rotor = from_ross(rr, 0.0).rotor
        assert rotor._split() is not None
        for w in (0.0, 123.4, 987.0, 2500.0):
            fast = rotor._read(w)
            rotor._split_made = None  # ROSS's assembly, read at this speed
            slow = rotor._read(w)
            del rotor._split_made
            for a, b in zip(fast, slow, strict=True):
                assert np.abs(a - b).max() <= 1e-13 * max(np.abs(b).max(), 1e-300)
