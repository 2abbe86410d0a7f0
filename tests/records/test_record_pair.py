"""GroundMotionPair: rotation, RotD100 against the peak over directions of single-component
spectra of the projected record, and read_at2 of two paths."""

from __future__ import annotations

import numpy as np
import pytest

from duhamel.records import GroundMotion, GroundMotionPair, read_at2
from duhamel.spectra import response_spectrum


def pair(seed: int = 0, n: int = 2000, dt: float = 0.01) -> GroundMotionPair:
    rng = np.random.default_rng(seed)
    t = dt * np.arange(n)
    env = (t / 2.0) ** 2 * np.exp(-t / 2.0)
    h1 = GroundMotion(env * rng.standard_normal(n), dt, "g", name=f"R{seed}_000")
    h2 = GroundMotion(0.7 * env * rng.standard_normal(n), dt, "g", name=f"R{seed}_090")
    return GroundMotionPair(h1, h2)


def test_rotation_composes_and_keeps_the_norm():
    p = pair()
    a = p.rotated(25.0).rotated(40.0)
    b = p.rotated(65.0)
    np.testing.assert_allclose(a.first.a, b.first.a, atol=1e-14 * p.first.pga)
    np.testing.assert_allclose(a.second.a, b.second.a, atol=1e-14 * p.first.pga)
    np.testing.assert_allclose(
        a.first.a**2 + a.second.a**2, p.first.a**2 + p.second.a**2, rtol=1e-12
    )
    assert p.name == "R0"


def test_rotd100_is_the_largest_single_direction_spectrum():
    p = pair(1)
    periods = np.array([0.1, 0.3, 1.0, 2.5])
    got = p.rotd100(periods)
    # independent: the projection on each of 180 directions as a single record
    directions = [p.rotated(float(th)).first for th in range(180)]
    psa = response_spectrum(directions, periods).psa[:, 0, :]
    np.testing.assert_allclose(got, psa.max(axis=0), rtol=1e-10)
    rd = p.rotd(periods, percentiles=(50, 100))
    np.testing.assert_allclose(rd.psa[0, 1], got, rtol=1e-14)
    np.testing.assert_allclose(rd.psa[0, 0], np.percentile(psa, 50, axis=0), rtol=1e-10)
    # one factor scales the pair's spectrum linearly
    np.testing.assert_allclose(p.scaled(1.7).rotd100(periods), 1.7 * got, rtol=1e-12)


def test_read_at2_of_two_paths_gives_a_pair(tmp_path):
    p = pair(2)
    p.write_at2(tmp_path / "R2_000.AT2", tmp_path / "R2_090.AT2")
    back = read_at2(tmp_path / "R2_000.AT2", tmp_path / "R2_090.AT2")
    assert isinstance(back, GroundMotionPair) and back.name == "R2"
    np.testing.assert_allclose(back.first.a, p.first.a, rtol=1e-15)
    np.testing.assert_allclose(back.second.a, p.second.a, rtol=1e-15)
    assert isinstance(read_at2(tmp_path / "R2_000.AT2"), GroundMotion)


def test_pair_pads_the_shorter_and_refuses_other_steps():
    a = GroundMotion([1.0, 2.0, 3.0], 0.01)
    b = GroundMotion([4.0, 5.0], 0.01)
    p = GroundMotionPair(a, b)
    assert p.second.a.tolist() == [4.0, 5.0, 0.0]
    with pytest.raises(ValueError, match="`second` has dt"):
        GroundMotionPair(a, GroundMotion([1.0, 2.0], 0.02))
    with pytest.raises(TypeError, match="`first`"):
        GroundMotionPair([1.0, 2.0], b)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="`angle`"):
        p.rotated(float("nan"))
