"""The example scripts run (smoke tests, so they cannot rot)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_duffing_quadratures_prints_the_table():
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "duffing_quadratures.py")],
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    ).stdout
    assert "1000 steps" in out and "506 steps" in out
    row_b = next(line for line in out.splitlines() if line.strip().startswith("b "))
    trapezoid, parabolic, _exact = (float(v) for v in row_b.split()[1:])
    assert trapezoid < parabolic and abs(trapezoid - 0.0348) < 5e-4


def test_lattice_from_matrixmarket() -> None:
    """The large-model route on a small lattice: M and K through mmwrite/mmread straight into
    a System, ten cubic springs, modes + static correction; the second System on the saved
    basis gives the same run bit for bit, and it matches the full model."""
    import importlib.util

    import numpy as np

    import duhamel

    spec = importlib.util.spec_from_file_location(
        "lattice", ROOT / "examples" / "lattice_mmread.py"
    )
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--small", "--steps", "1000"])
    sol, again = out["solution"], out["again"]
    assert out["format"] in ("coo_matrix", "coo_array") and out["n_dof"] == 512
    assert sol.stats.modes == 30 + 10 + 1  # one static vector per spring and the load
    assert np.array_equal(sol.x, again.x)
    # against every mode (the static correction makes 30 modes of 512 close to it)
    M, K = ex.lattice((8, 8, 8))
    full_system = duhamel.System(M.toarray(), K.toarray(), zeta=0.02)
    full_system.add_load(duhamel.loads.Harmonic(511, amplitude=100.0, omega=6.0))
    rng = np.random.default_rng(3)
    for dof in rng.choice(511, size=10, replace=False):
        full_system.add(duhamel.elements.Cubic(int(dof), k3=1e9))
    full = duhamel.solve(full_system, duhamel.Semianalytic(), t_end=1.0, dt=1e-3, dofs=[511])
    err = np.abs(sol.x - full.x).max() / np.abs(full.x).max()
    print(f"\n30 modes + correction vs all 512 modes at the tip: {err:.2e}")
    assert err < 2e-2  # measured 9.4e-3 (the load's dynamics in the truncated modes)


def test_spectra_example(tmp_path: Path) -> None:
    """Records and spectra: the .AT2 written and read back, the spectra consistent with each
    other (RotD100 >= each component; ductility 1 is the elastic spectrum)."""
    import importlib.util

    import numpy as np

    spec = importlib.util.spec_from_file_location("spectra_ex", ROOT / "examples" / "spectra.py")
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--save", str(tmp_path / "spectra.png")])
    assert (tmp_path / "spectra.png").stat().st_size > 10_000
    el, rd, duct = out["el"], out["rotd"], out["ductility"]
    assert np.all(rd.sd[0, 1] >= el.sd[:, 1].max(axis=0) * (1 - 1e-12))
    np.testing.assert_array_equal(duct.uy[0, 0], el.sd[0, 1])
    h1 = out["motions"][0]
    np.testing.assert_allclose(h1.a / 9.80665, ex.synthetic(1, 0.35), rtol=1e-7, atol=0)


def test_ida_example(tmp_path: Path) -> None:
    """IDA of the yielding frame on a few records: the fractiles are ordered and grow with
    the intensity; in the elastic range the drift is proportional to Sa(T1)."""
    import importlib.util

    import numpy as np

    spec = importlib.util.spec_from_file_location("ida_ex", ROOT / "examples" / "ida.py")
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--records", "5", "--save", str(tmp_path / "ida.png")])
    res = out["ida"]
    assert res.measures.shape == (5, 15) and np.all(np.isfinite(res.measures))
    f = res.fractiles()
    assert np.all(f[0] <= f[1]) and np.all(f[1] <= f[2]) and np.all(np.diff(f[1]) > 0)
    elastic = res.measures[:, 0] / res.intensities[0]  # 0.2 g: below yield
    np.testing.assert_allclose(res.measures[:, 1] / res.intensities[1], elastic, rtol=1e-9)


def test_journal_whirl_example() -> None:
    """Oil whirl on short journal bearings: the linear threshold's whirl is at half the
    speed, and in a run-up through it the subsynchronous whirl emerges within 15 % above the
    threshold at 0.4-0.55 x speed (below it only the broadband excitation's level)."""
    import importlib.util

    import duhamel

    spec = importlib.util.spec_from_file_location("whirl", ROOT / "examples" / "journal_whirl.py")
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.run(500.0, 780.0, 2.8, 1e-4, duhamel.Semianalytic())
    w_th = out["threshold"]
    assert 0.48 < out["whirl"] / w_th < 0.52
    onset = out["onset"]
    assert 0.95 * w_th < onset["speed"] < 1.15 * w_th
    assert 0.4 < onset["ratio"] < 0.55
    assert 0.0 < out["eccentricity"] < 1.0


def test_ground_motion_suite_example() -> None:
    """Three pairs scaled to the ASCE 7 MCE_R spectrum over 0.75-1.25 T_M and run on the
    isolated building in two orientations: the criterion holds, the results carry record,
    factor and orientation, and the building's symmetry in x and y gives the same isolator
    displacement (a vector's length) in both orientations."""
    import importlib.util

    import numpy as np

    spec = importlib.util.spec_from_file_location(
        "ground_motion_suite", ROOT / "examples" / "ground_motion_suite.py"
    )
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--pairs", "3", "--no-plot"])
    assert out["scaled"].passes
    ds = out["dataset"]
    assert ds.sizes["case"] == 6 and list(ds["orientation"].values) == [0.0, 90.0] * 3
    np.testing.assert_allclose(ds["factor"].values, np.repeat(out["scaled"].factors, 2))
    iso = ds["isolator"].values.reshape(3, 2)
    np.testing.assert_allclose(iso[:, 0], iso[:, 1], rtol=1e-6)
    assert np.all((iso > 0.05) & (iso < 2.0))


def test_opensees_frame_matches_opensees() -> None:
    """The OpenSees frame example: imported, run, and within 0.5 % of OpenSees' run."""
    import pytest

    try:
        import openseespy.opensees  # noqa: F401
    except Exception as exc:  # the wheel needs the system BLAS/LAPACK
        pytest.skip(reason=f"openseespy cannot be loaded: {exc}")
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "opensees_frame.py")],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    ).stdout
    line = next(x for x in out.splitlines() if x.startswith("largest difference"))
    assert float(line.split()[2]) < 5e-3
    assert "'Bilinear'" in out and "peak isolator displacement" in out


def test_rotor_analyses_example(tmp_path) -> None:
    """The frequency response, Level I and critical speed map example runs and writes its
    four figures."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "rotor_analyses.py"), "--save", str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    ).stdout
    assert "Level I at 1100 rad/s" in out and "meets critical speed 0" in out
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["rotor_frf.png", "rotor_frf_map.png", "rotor_level1.png", "rotor_ucs_map.png"]


def test_magnetic_bearing_example(tmp_path) -> None:
    """The magnetic-bearing example: the good tuning is stable with a peak sensitivity in
    ISO 14839-3 zone A (below 3), the soft one is found unstable; the figure is written."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "magnetic_bearing.py"), "--save", str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    ).stdout
    peak = float(out.split("peak sensitivity ")[1].split()[0])
    assert 1.0 < peak < 3.0 and "stable = False" in out
    assert (tmp_path / "rotor_amb.png").exists()


def test_cracked_rotor_example(tmp_path) -> None:
    """The cracked rotor's run-up: the 2x and 3x order amplitudes peak near 1/2 and 1/3 of
    the critical speed (a little above: the run-up's lag), as Gasch and Mayes & Davies put
    them; the figure is written."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "cracked_rotor.py"), "--save", str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    ).stdout
    for line in out.splitlines()[:2]:
        half = float(line.split("2x peak at ")[1].split("(")[1].split()[0])
        third = float(line.split("3x peak at ")[1].split("(")[1].split()[0])
        assert 0.49 < half < 0.54 and 0.32 < third < 0.36
    assert (tmp_path / "rotor_crack.png").exists()


def test_misaligned_rotor_example(tmp_path) -> None:
    """The misaligned coupling's run-up: the 2x order peaks near half the first critical
    speed and the 3x (the angular part's) near a third (a little above: the run-up's lag);
    the figure is written."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "misaligned_rotor.py"), "--save", str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    ).stdout
    line = next(s for s in out.splitlines() if s.startswith("first critical"))
    half = float(line.split("2x peak at ")[1].split("(")[1].split()[0])
    third = float(line.split("3x peak at ")[1].split("(")[1].split()[0])
    assert 0.49 < half < 0.54 and 0.32 < third < 0.36
    assert (tmp_path / "rotor_misalignment.png").exists()


def test_asce7_isolated_study_example(tmp_path: Path) -> None:
    """The ASCE 7 study of the OpenSees example's isolated frame (issue 39), on 7 pairs of
    15 s: the statistics equal a hand computation over solve_many's results (1e-12), the
    report (HTML and Markdown) holds every table and figure and prints the study's
    numbers, the ELF values bracket as bounds do."""
    import importlib.util

    import numpy as np
    import pytest

    try:
        import openseespy.opensees  # noqa: F401
    except Exception as exc:  # the wheel needs the system BLAS/LAPACK
        pytest.skip(reason=f"openseespy cannot be loaded: {exc}")
    sys.path.insert(0, str(ROOT / "tests" / "_support"))
    from _design_study import QUANTITIES, check_report, hand_statistics

    spec = importlib.util.spec_from_file_location(
        "asce7_study", ROOT / "examples" / "asce7_isolated_study.py"
    )
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = ex.main(["--pairs", "7", "--duration", "15", "--out", str(tmp_path / "study.html")])
    study, elf = out["study"], out["elf"]
    assert list(study.models) == ["lower", "nominal", "upper"]
    assert study.ensemble.stats.runs == 7 * 2 * 3
    lo, nom, up = (elf.bounds[n] for n in ("lower", "nominal", "upper"))
    assert lo.d_m > nom.d_m > up.d_m and lo.t_m > nom.t_m > up.t_m
    hand = hand_statistics(study)
    for model, quantities in study.statistics.items():
        for key in QUANTITIES:
            for kind in ("design", "mean", "mean_plus_sigma", "max"):
                np.testing.assert_allclose(
                    quantities[key][kind], hand[model][key][kind], rtol=1e-12, atol=0
                )
    check_report(study, out["html"], out["md"])
