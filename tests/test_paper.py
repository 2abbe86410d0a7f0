"""The paper's examples (duhamel.paper) at small sizes, their claims, and `duhamel reproduce`.

The numbers asserted are the paper's or NOTES.md's (to the digits they are stated with), or
structural facts (orderings, orders of convergence); none is fitted to this implementation.
"""

from __future__ import annotations

import itertools
import math

import matplotlib
import numpy as np
import pytest

import duhamel
from duhamel import exact
from duhamel.cli import main
from duhamel.paper import (
    NAMES,
    Claim,
    cpu_ratios,
    fig1,
    fig2,
    fig3,
    fig4,
    fig8,
    figs5to7,
    fit_order,
    reproduce,
)
from duhamel.paper import duffing as pd
from duhamel.paper import figures as pf
from duhamel.paper import pendulum as pp
from duhamel.paper.report import parse_names, render_report

matplotlib.use("Agg")

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def f1():
    # dt/T up to 10 (past the first unstable intervals of (a) and (c)), a coarse grid: the
    # maxima and interval ends are refined by root finding, not read off the grid.
    return fig1(n_points=161, dt_over_T=(1e-3, 10.0))


@pytest.fixture(scope="module")
def f2():
    return fig2(n_points=41)


@pytest.fixture(scope="module")
def f3():
    return fig3()  # the paper's size: 1000 steps, milliseconds


@pytest.fixture(scope="module")
def f4():
    return fig4(convergence_steps=(10, 20, 40, 80))


@pytest.fixture(scope="module")
def bes():
    return figs5to7(n_fine=201)


@pytest.fixture(scope="module")
def f8():
    return fig8(steps=(10, 20, 40, 80, 160))


# ---------------------------------------------------------------------------------- Fig. 1


def test_fig1_intervals_and_maxima_as_in_notes(f1):
    # NOTES.md section 2: (a) max 1.1055, first unstable on (0.500, 0.999); (b) never above
    # 1; (c) max 1.2002, first on (0.933, 1.357). Each to the digits NOTES.md gives.
    where_a, peak_a = f1.peaks["a"]
    where_c, peak_c = f1.peaks["c"]
    (lo_a, hi_a), (lo_c, hi_c) = f1.intervals["a"][0], f1.intervals["c"][0]
    assert abs(peak_a - 1.1055) <= 5e-5 and abs(peak_c - 1.2002) <= 5e-5
    assert abs(lo_a - 0.500) <= 5e-4 and abs(hi_a - 0.999) <= 1e-3 + 1e-9
    assert abs(lo_c - 0.933) <= 5e-4 and abs(hi_c - 1.357) <= 5e-4
    assert f1.intervals["b"] == []
    assert f1.chart.curve("scheme (b)").max() <= 1.0 + 1e-12
    assert f1.touch_max <= 1.0 + 1e-12
    # scheme (a) in closed form: unstable exactly on (k + 1/2, k + 1), max at k + 3/4
    assert where_a == pytest.approx(0.75, abs=1e-6)
    assert f1.intervals["a"][1] == pytest.approx((1.5, 2.0), abs=1e-8)
    assert 0.9 < where_c < 1.0


def test_fig1_claims(f1):
    claims = f1.claims()
    assert len(claims) == 3 and all(c.holds is True for c in claims)
    assert "1.105542" in claims[0].ours and "1.200195" in claims[0].ours


# ---------------------------------------------------------------------------------- Fig. 2


def test_fig2_stability_and_the_sign_of_eq25(f2):
    for chart in f2.charts.values():
        for label in ("scheme (b)", "Newmark"):
            assert chart.curve(label).max() <= 1.0 + 1e-12
        # scheme (b) damps large steps, Newmark's average acceleration returns to 1
        assert chart.curve("scheme (b)")[-1] < 1e-3
        assert chart.curve("Newmark")[-1] > 0.999
    # eq. 26 holds for +alpha; the printed -alpha turns (1 - alpha) into (1 + alpha)
    assert f2.eq26_ratio[1] == pytest.approx(1.0, abs=1e-3)
    assert f2.eq26_ratio[-1] == pytest.approx(-(1 + 0.3) / (1 - 0.3), abs=1e-3)
    # the engine's Newmark curve is the closed form's (realization accuracy ~1e-9)
    assert f2.closed_form_deviation < 1e-8
    verdicts = [c.holds for c in f2.claims()]
    assert verdicts == [True, True, False, True, None]


# ---------------------------------------------------------------------------------- Fig. 3


def test_fig3_error_ordering_and_values(f3):
    e = {k: r.max_eps for k, r in f3.runs.items()}
    # NOTES.md section 2: default (trapezoid) 0.035, Newmark 0.105, parabolic 0.166,
    # cubic Hermite 7e-5
    assert abs(e[pd.DEFAULT] - 0.035) < 5e-4
    assert abs(e[pd.NEWMARK] - 0.105) < 5e-4
    assert abs(e[pd.PARABOLIC] - 0.166) < 5e-4
    assert abs(e[pd.HERMITE] - 7e-5) < 5e-6
    assert e[pd.HERMITE] < e[pd.DEFAULT] < e[pd.NEWMARK] < e[pd.PARABOLIC]
    assert f3.runs[pd.DEFAULT].t.size == 1001
    assert f3.runs[pd.DEFAULT].t[-1] == pytest.approx(10 * 2 * math.pi)
    verdicts = [c.holds for c in f3.claims()]
    assert verdicts == [True, False, False, True]


def test_fig3_errors_are_normalised_against_cn(f3):
    # recompute one run independently: eps = (w - w_exact)/w0, sigma = (w' - w'_exact)/(w0 omega)
    system = duhamel.System(np.eye(1), np.eye(1)).add(duhamel.elements.Cubic(0, 4.0))
    sol = duhamel.solve(system, duhamel.Newmark(), t_end=20 * np.pi, dt=2 * np.pi / 100, x0=[1.0])
    w, v = exact.duffing(sol.t, 1.0, 4.0, 1.0)
    run = f3.runs[pd.NEWMARK]
    np.testing.assert_array_equal(run.eps, sol.x[:, 0] - w)
    np.testing.assert_array_equal(run.sigma, sol.v[:, 0] - v)
    assert run.eps[0] == 0.0 and run.sigma[0] == 0.0


def test_fig3_small_size_runs():
    small = fig3(periods=1, steps_per_period=50)
    assert small.runs[pd.DEFAULT].t.size == 51
    # second order: halving omega dt from 2 pi/50 to 2 pi/100 over one period
    coarse = small.runs[pd.DEFAULT].max_eps
    fine = fig3(periods=1).runs[pd.DEFAULT].max_eps
    assert math.log2(coarse / fine) == pytest.approx(2.0, abs=0.1)


def test_cpu_ratios_small():
    data = cpu_ratios(repeats=3, periods=100)
    assert data.steps == 10_000 and data.repeats == 3
    for times in data.seconds_per_step.values():
        assert times.shape == (3,) and np.all(times > 0)
    # the closed-form cubic step is cheaper than Newmark's Newton step (measured 0.45-0.6)
    assert data.ratio(pd.DEFAULT) < 1.0
    (claim, *_info) = data.claims()
    assert claim.holds == (data.ratio(pd.DEFAULT) <= 0.6)
    assert all(c.holds is None for c in _info)


# ---------------------------------------------------------------------------------- Fig. 4


def test_fig4_eliminated_beats_newmark_estimate_does_not(f4):
    e = {k: f4.max_error(k) for k in f4.w}
    # NOTES.md section 3: Newmark 6.6; docs/mass.md: eliminate 0.413, estimate 17.7
    assert abs(e[pp.NEWMARK] - 6.6) < 0.05
    assert abs(e[pp.ELIMINATE] - 0.413) < 5e-4
    assert abs(e[pp.ESTIMATE] - 17.7) < 0.05
    assert e[pp.ELIMINATE] < e[pp.NEWMARK] < e[pp.ESTIMATE]
    assert e[pp.EQ30] < 1e-5  # eq. 30: exact transition with zeta = -a/2
    assert f4.t[-1] == pytest.approx(5 * 2 * np.pi) and f4.t.size == 51
    np.testing.assert_allclose(
        f4.exact,
        exact.decaying_mass_pendulum(f4.t, 0.1, 1.0, 1.0, 2.0, 1.0)[0],
        rtol=0,
        atol=0,
    )
    assert [c.holds for c in f4.claims()] == [True, True, False, True]


def test_fig4_converges_at_second_order(f4):
    steps = sorted(f4.convergence)
    errors = [f4.convergence[n] for n in steps]
    assert errors[0] == pytest.approx(f4.max_error(pp.ELIMINATE), rel=1e-12)
    assert fit_order([1 / n for n in steps[1:]], errors[1:]) == pytest.approx(2.0, abs=0.1)


# -------------------------------------------------------------------------------- Figs. 5-8


def test_figs5to7_exact_solution_and_run(bes):
    # eq. 44 against DOP853 (the acceptance: 1e-9 or better)
    assert bes.ode_deviation < 1e-9
    assert bes.mass_ratio[0] == 1.0 and bes.mass_ratio[-1] == pytest.approx(math.exp(-2.0))
    assert bes.x[0] == pytest.approx(1.0, abs=1e-12) and abs(bes.v[0]) < 1e-12
    assert bes.t[-1] == pytest.approx(20.0)
    # the semi-analytic run drawn (T/40): second-order accurate, error 0.143 (docs/mass.md)
    assert abs(bes.max_error - 0.143) < 5e-4
    assert [c.holds for c in bes.claims()] == [True, None, None]


def test_fig8_order_two(f8):
    assert f8.order_steps == (20, 40, 80, 160)
    assert f8.order == pytest.approx(2.0, abs=0.1)
    errors = [f8.errors[n] for n in f8.steps]
    assert all(b < a for a, b in itertools.pairwise(errors))
    # Newmark, also second order, is less accurate at every step on this case
    assert all(f8.newmark_errors[n] > f8.errors[n] for n in f8.steps)
    assert f8.newmark_order == pytest.approx(2.0, abs=0.1)
    assert [c.holds for c in f8.claims()] == [True, True, None]


# ---------------------------------------------------------------------------------- figures


def test_figures_have_the_papers_axes(f1, f2, f3, f4, bes, f8):
    fig = pf.plot_fig1(f1)
    assert [ax.get_xscale() for ax in fig.axes] == ["log"] * 3
    assert fig.axes[0].get_ylabel() == r"$|\lambda|$"
    fig = pf.plot_fig2(f2)
    assert fig.axes[0].get_xlabel() == r"$\Delta t\,/\,T$" and len(fig.axes[0].get_lines()) == 6
    fig = pf.plot_fig3(f3)
    assert len(fig.axes) == 3 and "epsilon" in fig.axes[0].get_xlabel()
    assert "sigma" in fig.axes[0].get_ylabel()
    fig = pf.plot_fig4(f4)
    assert fig.axes[1].get_xlabel() == r"$t\,/\,T$" and "epsilon" in fig.axes[1].get_ylabel()
    assert pf.plot_fig5(bes).axes[0].get_ylabel() == r"$m(t)\,/\,m_0$"
    assert len(pf.plot_fig6(bes).axes) == 2
    assert "x_0" in pf.plot_fig7(bes).axes[0].get_xlabel()
    fig = pf.plot_fig8(f8)
    assert fig.axes[1].get_xscale() == "log" and fig.axes[1].get_yscale() == "log"


# ------------------------------------------------------------------------- report and CLI


def test_parse_names_and_claim():
    assert parse_names("fig8,cpu, fig1") == ("fig1", "cpu", "fig8")
    with pytest.raises(ValueError, match="unknown example 'bogus'"):
        parse_names("fig1,bogus")
    assert NAMES == ("fig1", "fig2", "fig3", "cpu", "fig4", "fig5", "fig6", "fig7", "fig8")
    assert Claim("x", "p", "o", False).verdict == "does not hold"
    assert Claim("x", "p", "o", None).verdict == "(information)"


def test_reproduce_writes_report_and_figures(tmp_path):
    run = reproduce(
        tmp_path / "a" / "b", only=["fig6", "cpu"], options={"cpu": {"repeats": 1, "periods": 10}}
    )
    names = sorted(p.name for p in run.files)
    assert names == ["fig6_displacement_velocity.png", "report.md"]  # fig6 only, not 5, 7
    text = run.report.read_text()
    assert "## Figs. 5-7" in text and "## CPU time against Newmark" in text
    assert "![fig6](fig6_displacement_velocity.png)" in text
    assert "Section 4.4" in text and "## Fig. 3" not in text
    assert run.report.parent == tmp_path / "a" / "b"


def test_report_escapes_table_cells():
    from duhamel.paper.report import EXAMPLES, ExampleResult

    result = ExampleResult(EXAMPLES[0], None, [Claim("|a|", "p", "o", False)], {}, 0.1)
    text = render_report([result], seconds=1.0)
    assert "| \\|a\\| | p | o | **does not hold** |  |" in text
    assert "1 statements checked: 0 hold, 1 do not hold" in text


def test_cli_reproduce_only(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["reproduce", "--out", str(out), "--only", "fig3,fig4,fig5"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""  # not a terminal: no progress bar
    assert "fig3      2 hold, 2 do not hold" in captured.out
    assert f"wrote 4 files to {out}" in captured.out
    for name in ("fig3", "fig4", "fig5"):
        png = out / pf.FIGURES[name]
        assert png.read_bytes()[:8] == PNG and png.stat().st_size > 10_000
    assert not (out / pf.FIGURES["fig6"]).exists()
    text = (out / "report.md").read_text()
    assert "duhamel reproduce --out" in text and "--only fig3,fig4,fig5" in text
    assert "max \\|eps\\| 0.0348 vs Newmark 0.105 | holds" in text
    assert "max \\|eps\\| 0.166 vs Newmark 0.105 | **does not hold**" in text
    assert "max \\|eps\\| 0.413 vs Newmark 6.58 | holds" in text


def test_cli_reproduce_quiet(tmp_path, capsys):
    assert main(["reproduce", "--out", str(tmp_path), "--only", "fig3", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    assert (tmp_path / "report.md").exists()


def test_cli_reproduce_bogus_is_exit_2(tmp_path, capsys):
    assert main(["reproduce", "--out", str(tmp_path), "--only", "fig3,bogus"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: duhamel reproduce")
    assert "argument --only: unknown example 'bogus' (choose from fig1, fig2," in err
    assert not (tmp_path / "report.md").exists()


def test_cli_reproduce_unwritable_out_exits_1(tmp_path, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a directory")
    assert main(["reproduce", "--out", str(blocker), "--only", "fig3", "--quiet"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("duhamel: error: cannot write to") and err.count("\n") == 1


def test_cli_help_lists_reproduce(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "reproduce" in out and "demo" in out
    assert main(["reproduce", "--help"]) == 0
    assert "--only LIST" in capsys.readouterr().out
