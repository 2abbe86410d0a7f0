"""Tests for the ``duhamel`` command line, the bundled demo and examples/shear_building.py."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import duhamel
from duhamel.cli import main
from duhamel.demo import G, run_demo, shear_building, synthetic_record

ROOT = Path(__file__).resolve().parents[2]
SUMMARY_LABELS = (
    "natural periods",
    "peak roof displ.",
    "peak drift ratio",
    "peak base shear",
    "mode-steps/s",
)


def run_module(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "duhamel", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=60,
    )


@pytest.fixture(scope="module")
def demo():
    return run_demo()


# ------------------------------------------------------------------------- arguments


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"duhamel {duhamel.__version__}\n"


def test_python_m_duhamel_version():
    proc = run_module("--version")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == f"duhamel {duhamel.__version__}"


def test_help_lists_subcommands(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "demo" in out and "--version" in out


@pytest.mark.parametrize("argv", [[], ["demo", "--bogus"], ["nonsense"], ["demo", "--out"]])
def test_bad_arguments_exit_2(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: duhamel") and "error:" in err


# ------------------------------------------------------------------------------ demo


def test_demo_writes_plot_and_summary(tmp_path, capsys):
    out = tmp_path / "new" / "dir"  # created, parents included
    assert main(["demo", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    for label in SUMMARY_LABELS:
        assert label in text
    assert "T1 = 1.000 s" in text
    png = out / "demo.png"
    assert png.stat().st_size > 10_000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    summary = json.loads((out / "demo_summary.json").read_text())
    assert summary["version"] == duhamel.__version__
    assert summary["steps"] == 3000 and summary["modes"] == 10
    assert summary["periods_s"][0] == pytest.approx(1.0, rel=1e-9)


def test_demo_no_plot(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--no-plot"]) == 0
    assert "peak roof displ." in capsys.readouterr().out
    assert not (tmp_path / "demo.png").exists()
    assert (tmp_path / "demo_summary.json").exists()


def test_unwritable_out_exits_1_without_traceback(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a directory")
    proc = run_module("demo", "--out", str(blocker / "sub"), "--no-plot")
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("duhamel: error:")
    assert str(blocker / "sub") in lines[0]


def test_out_is_a_file_exits_1(tmp_path, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a directory")
    assert main(["demo", "--out", str(blocker)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("duhamel: error: cannot create")


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root can write")
def test_read_only_out_exits_1(tmp_path, capsys):
    tmp_path.chmod(0o500)
    try:
        assert main(["demo", "--out", str(tmp_path), "--no-plot"]) == 1
    finally:
        tmp_path.chmod(0o700)
    assert capsys.readouterr().err.startswith("duhamel: error: cannot write")


def test_model_and_record():
    basis = shear_building().modal()
    assert 2 * np.pi / basis.omega[0] == pytest.approx(1.0, rel=1e-12)
    t, a = synthetic_record()
    _, a2 = synthetic_record()
    np.testing.assert_array_equal(a, a2)  # deterministic
    assert t.size == 2001 and t[-1] == pytest.approx(20.0)
    assert np.abs(a).max() == pytest.approx(0.3 * G, rel=1e-12)
    assert a[0] == 0.0 and a[-1] == 0.0  # no jump when the record ends


def reference_response(demo) -> tuple[np.ndarray, np.ndarray]:
    """Exact first-order-hold state-space integration with scipy.linalg.expm.

    ``z = [x, v]``, ``z' = A z + B a_g(t)`` with ``B = [0, -r]``; ``a_g`` is linear within
    each step, so ``z_{k+1} = F z_k + G1 u_k + G2 (u_{k+1} - u_k) / h`` where ``F, G1, G2``
    come from the exponential of the augmented matrix (Van Loan). The damping matrix is
    rebuilt from an independent eigensolution: ``C = M V diag(2 zeta omega) V^T M``.
    """
    M, K = np.asarray(demo.system.M), np.asarray(demo.system.K)
    n = M.shape[0]
    w2, V = scipy.linalg.eigh(K, M)
    C = M @ V @ np.diag(2 * 0.05 * np.sqrt(w2)) @ V.T @ M
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    t = demo.solution.t
    h = t[1] - t[0]
    aug = np.zeros((2 * n + 2, 2 * n + 2))
    aug[: 2 * n, : 2 * n] = A
    aug[n : 2 * n, 2 * n] = -1.0
    aug[2 * n, 2 * n + 1] = 1.0
    E = scipy.linalg.expm(aug * h)
    F, G1, G2 = E[: 2 * n, : 2 * n], E[: 2 * n, 2 * n], E[: 2 * n, 2 * n + 1] / h
    u = np.interp(t, demo.t_g, demo.a_g, right=0.0)
    z = np.zeros((t.size, 2 * n))
    for k in range(t.size - 1):
        z[k + 1] = F @ z[k] + G1 * u[k] + G2 * (u[k + 1] - u[k])
    total_acc = -(z[:, :n] @ K + z[:, n:] @ C) @ Minv  # M (a + r a_g) = -(K x + C v)
    return z, total_acc


def test_demo_matches_exact_state_space_reference(demo):
    z, total_acc = reference_response(demo)
    sol, n = demo.solution, demo.system.n_dof
    assert sol.t.size == 3001 and sol.t[-1] == pytest.approx(30.0)
    # Measured: 2.2e-14 (x, v) and 3.0e-14 (base shear) of the peak: ~50x margin below.
    roof_ref = z[:, n - 1]
    assert np.abs(sol.x[:, -1] - roof_ref).max() <= 1e-12 * np.abs(roof_ref).max()
    assert np.abs(sol.x - z[:, :n]).max() <= 1e-12 * np.abs(z[:, :n]).max()
    assert np.abs(sol.v - z[:, n:]).max() <= 1e-12 * np.abs(z[:, n:]).max()
    shear_ref = -total_acc @ np.diag(np.asarray(demo.system.M))
    assert np.abs(demo.base_shear - shear_ref).max() <= 1e-12 * np.abs(shear_ref).max()
    assert demo.roof_peak == pytest.approx(roof_ref[np.argmax(np.abs(roof_ref))], rel=1e-12)


def test_demo_post_processing(demo):
    x = demo.solution.x
    drift = np.abs(np.diff(np.column_stack([np.zeros(x.shape[0]), x]), axis=1)) / 3.5
    assert demo.drift_peak == pytest.approx(drift.max(), rel=1e-15)
    assert demo.drift_storey == np.unravel_index(np.argmax(drift), drift.shape)[1] + 1


# -------------------------------------------------------------------------- example


def test_example_script_runs(tmp_path):
    out = tmp_path / "sb.png"
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "shear_building.py"), str(out)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=60,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert proc.returncode == 0, proc.stderr
    assert "peak roof displacement" in proc.stdout
    assert out.stat().st_size > 10_000


def test_missing_matplotlib_is_a_clear_error(tmp_path, capsys, monkeypatch):
    for name in ("matplotlib", "matplotlib.figure"):
        monkeypatch.setitem(sys.modules, name, None)  # makes importing them fail
    assert main(["demo", "--out", str(tmp_path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""  # checked before the run
    assert captured.err == (
        "duhamel: error: the demo plot needs matplotlib: pip install 'duhamel[plot]' "
        "(or use --no-plot)\n"
    )
