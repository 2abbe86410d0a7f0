"""Rotor.frequency_response / frequency_response_map against dense complex solves written out
here, against the unbalance response (an unbalance is two unit forces in quadrature), and the
input checks."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft

matplotlib.use("Agg")


def rotor(n_shafts: int = 4, tabulated: bool = False) -> Rotor:
    """Damped, cross-coupled, anisotropic bearings; optionally tabulated against speed."""
    if tabulated:
        b0 = Bearing(0, [8e6, 1.2e7], [6e6, 1e7], kxy=[1e6, 3e6], kyx=[-1e6, -3e6],
                     cxx=[400.0, 900.0], cyy=[300.0, 700.0], speeds=[0.0, 1000.0])  # fmt: skip
    else:
        b0 = Bearing(0, 1e7, 8e6, kxy=2e6, kyx=-2e6, cxx=500.0, cyy=400.0, cxy=30.0, cyx=-20.0)
    b1 = Bearing(n_shafts, 1.1e7, 9e6, cxx=600.0, cyy=450.0)
    mid = n_shafts // 2
    return Rotor(
        [Shaft(1.0 / n_shafts, 0.05, material=STEEL)] * n_shafts,
        [Disk(mid, 30.0, 0.6, 0.3)],
        [b0, b1],
        rayleigh=(0.5, 1e-5),
    )


def dense(model: Rotor, speed: float, w: float, inputs, outputs, at: float | None = None):
    """``(K - w^2 M + i w (C + speed G))^-1`` restricted to the dofs, with the matrices at
    `at` (default `speed`): numpy's dense LU and one step of iterative refinement, the
    residual in extended precision (``clongdouble``), so that the reference is the exact
    solution of the rounded matrix (the plain LU alone is off by its condition number,
    up to 1e7 near the resonances, times round-off)."""
    M, K, C, G = model.matrices(speed if at is None else at)
    A = K - w**2 * M + 1j * w * (C + speed * G)
    B = np.zeros((A.shape[0], len(inputs)), dtype=complex)
    B[inputs, np.arange(len(inputs))] = 1.0
    x = np.linalg.solve(A, B)
    res = B.astype(np.clongdouble) - A.astype(np.clongdouble) @ x.astype(np.clongdouble)
    x = x + np.linalg.solve(A, res.astype(complex))
    return x[outputs]


def rel(a, b) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.mark.parametrize("n_shafts", [4, 40])  # 40: 164 dofs, the banded (gbsv) route
def test_receptances_equal_dense_solve(n_shafts):
    model = rotor(n_shafts)
    mid = n_shafts // 2
    ws = np.linspace(5.0, 2500.0, 37)
    inputs = [(mid, "x"), (mid, "y"), f"theta_y_{mid}", 0]
    outputs = ["x_0", (mid, "y"), 4 * mid + 2, (n_shafts, "x")]
    frf = model.frequency_response(700.0, ws, inputs, outputs)
    assert frf.response.shape == (ws.size, 4, 4)
    ins = [model.dof(mid, "x"), model.dof(mid, "y"), model.dof(mid, "theta_y"), 0]
    outs = [0, model.dof(mid, "y"), model.dof(mid, "theta_x"), model.dof(n_shafts, "x")]
    assert frf.inputs == tuple(ins) and frf.outputs == tuple(outs)
    ref = np.stack([dense(model, 700.0, w, ins, outs) for w in ws])
    err = rel(frf.response, ref)
    print(f"\nn_dof {model.n_dof}: receptances vs dense solve {err:.1e}")
    assert err < 1e-12


def test_speed_dependent_coefficients_and_the_map():
    """Tabulated bearings: the coefficients are those of the spin speed (not of the
    frequency); synchronous: of each frequency; the map is the stack of single speeds."""
    model = rotor(tabulated=True)
    ws = np.linspace(20.0, 1500.0, 25)
    ins, outs = [8, 9], [8, 9, 0]
    frf = model.frequency_response(600.0, ws, ins, outs)
    ref = np.stack([dense(model, 600.0, w, ins, outs) for w in ws])
    assert rel(frf.response, ref) < 1e-12
    sync = model.frequency_response("synchronous", ws, ins, outs)
    ref = np.stack([dense(model, w, w, ins, outs) for w in ws])
    assert sync.speed == "synchronous" and rel(sync.response, ref) < 1e-12
    speeds = np.array([0.0, 300.0, 900.0])
    fmap = model.frequency_response_map(speeds, ws, ins, outs)
    assert fmap.response.shape == (3, ws.size, 3, 2)
    for k, s in enumerate(speeds):
        one = model.frequency_response(s, ws, ins, outs).response
        np.testing.assert_array_equal(fmap.at(k).response, one)


def test_unbalance_is_two_forces_in_quadrature():
    """An unbalance m_e at a node is the force m_e W^2 (1, -i) on (x, y) at W = speed: the
    synchronous receptances reproduce unbalance_response."""
    model = rotor(tabulated=True)
    speeds = np.linspace(50.0, 1000.0, 40)
    m_e = 2e-4
    frf = model.frequency_response("synchronous", speeds, ["x_2", "y_2"], list(range(20)))
    ours = m_e * speeds[:, None] ** 2 * (frf.response[:, :, 0] - 1j * frf.response[:, :, 1])
    ref = model.unbalance_response(speeds, [(2, m_e, 0.0)]).response
    assert rel(ours, ref) < 1e-12


def test_plots_show_the_response():
    model = rotor()
    ws = np.linspace(10.0, 1500.0, 30)
    frf = model.frequency_response(300.0, ws, ["x_2"], ["x_2", "y_2"])
    mag, ph = frf.plot_bode(1, 0)
    np.testing.assert_allclose(mag.lines[0].get_ydata(), np.abs(frf.response[:, 1, 0]))
    np.testing.assert_allclose(ph.lines[0].get_ydata(), np.degrees(np.angle(frf.response[:, 1, 0])))
    assert "y_2 / x_2" in mag.get_title()
    ax = frf.plot_nyquist()
    np.testing.assert_allclose(ax.lines[0].get_xdata(), frf.response[:, 0, 0].real)
    fmap = model.frequency_response_map([0.0, 500.0, 1000.0], ws, "x_2", "x_2")
    ax = fmap.plot_map()
    mesh = ax.collections[0].get_array()
    np.testing.assert_allclose(
        np.ravel(mesh), np.log10(np.abs(fmap.response[:, :, 0, 0])).T.ravel()
    )


def test_refuses_bad_input():
    model = rotor()
    ws = [10.0, 20.0]
    with pytest.raises(ValueError, match="`inputs`: no dof is labelled 'q_2'"):
        model.frequency_response(0.0, ws, ["q_2"], [0])
    with pytest.raises(ValueError, match="`outputs`: dof 20 is not in"):
        model.frequency_response(0.0, ws, [0], [20])
    with pytest.raises(ValueError, match="`outputs` is empty"):
        model.frequency_response(0.0, ws, [0], [])
    with pytest.raises(ValueError, match="'synchronous'"):
        model.frequency_response("sync", ws, [0], [0])
    with pytest.raises(ValueError, match="`frequencies` is empty"):
        model.frequency_response(0.0, [], [0], [0])
    with pytest.raises(ValueError, match="frequencies"):
        model.frequency_response(0.0, [1.0, np.nan], [0], [0])
    with pytest.raises(TypeError, match="`inputs`"):
        model.frequency_response(0.0, ws, [True], [0])
    free = Rotor((), [Disk(0, 10.0, 0.1, 0.05)])  # no support: K = 0
    with pytest.raises(ValueError, match="singular"):
        free.frequency_response(0.0, [0.0], [0], [0])  # a rigid body at zero frequency
