"""Regression tests of issue 24: bad input and faults in records, spectra, devices,
ensembles, stores and rotors (every example of the issue), against the contract of
docs/errors.md: a finite result, or an exception naming the parameter, the file or the
store and what is damaged."""

from __future__ import annotations

import json
import pathlib
import shutil

import numpy as np
import pytest

import duhamel
from duhamel.ensemble import IDA, fractiles, solve_many
from duhamel.records import GroundMotion, read_at2, read_text
from duhamel.spectra import ductility_spectrum, response_spectrum, rotd

zarr = pytest.importorskip("zarr")
from duhamel.store import Store, StoreError, resume  # noqa: E402
from duhamel.store._codec import pack, unpack  # noqa: E402

AT2 = (
    "PEER NGA STRONG MOTION DATABASE RECORD\nDEMO\nACCELERATION TIME SERIES IN UNITS OF G\n"
    "NPTS=    3, DT= {dt} SEC\n  .1000E-01 -.2000E-01  .0000E+00\n"
)


# -- records: silent wrong data --------------------------------------------------------------


def test_at2_header_dt_with_a_fortran_d_exponent(tmp_path: pathlib.Path) -> None:
    p = tmp_path / "D.AT2"
    p.write_text(AT2.format(dt="5.0D-03"))
    assert read_at2(p).dt == 5.0e-3
    p.write_text(AT2.format(dt=".5d-2"))
    assert read_at2(p).dt == 5.0e-3
    for bad in ("0.0", "-1.0", "1D999"):
        p.write_text(AT2.format(dt=bad))
        with pytest.raises(ValueError, match=r"D\.AT2, line 4: DT"):
            read_at2(p)


def test_at2_value_beyond_the_double_range_names_line_and_column(tmp_path: pathlib.Path) -> None:
    p = tmp_path / "big.AT2"
    p.write_text(AT2.format(dt="0.01").replace(".0000E+00", "1.0E+999"))
    with pytest.raises(ValueError, match=r"big\.AT2, line 5, column \d+: .*overflows"):
        read_at2(p)


def test_read_text_checked_arguments(tmp_path: pathlib.Path) -> None:
    p = tmp_path / "rec.txt"
    p.write_text("0.0 1.0\n0.01 2.0\n0.02 3.0\n0.03 4.0\n0.04 5.0\n")
    with pytest.raises(ValueError, match=r"`skip_rows`.*non-negative"):
        read_text(p, units="g", time_column=0, skip_rows=-3)
    for dt in ("0.01", True, b"1"):
        with pytest.raises(TypeError, match="`dt`"):
            read_text(p, units="g", dt=dt, column=1)
    with pytest.raises(TypeError, match="`column`"):
        read_text(p, units="g", dt=0.01, column=1.5)
    with pytest.raises(ValueError, match="`column` and `time_column`"):
        read_text(p, units="g", time_column=0, column=0)
    with pytest.raises(TypeError, match="`flatten`"):
        read_text(p, units="g", dt=0.01, flatten="no")
    # the good calls still read the right data
    assert read_text(p, units="m/s^2", time_column=0, skip_rows=2).a.tolist() == [3.0, 4.0, 5.0]


def test_ground_motion_and_scaled_use_checked_conversions() -> None:
    for dt in ("0.01", True, b"1"):
        with pytest.raises(TypeError, match="`dt`"):
            GroundMotion([0.0, 1.0], dt=dt)
    gm = GroundMotion([0.0, 1.0, -1.0], dt=0.01)
    with pytest.raises(TypeError, match="`factor`"):
        gm.scaled("2")
    with pytest.raises(ValueError, match=r"`factor`.*double range"):
        GroundMotion([0.0, 10.0, -1.0], dt=0.01).scaled(1e308)


def test_ida_fractiles_treat_collapses_as_infinite() -> None:
    m = np.array([[1.0], [2.0], [np.inf]])
    res = IDA(np.array([1.0]), m, ["a", "b", "c"], "PGA", np.ones((3, 1)))
    f = res.fractiles((0, 16, 50, 51, 84, 100))[:, 0]
    assert f[2] == np.median([1.0, 2.0, np.inf]) == 2.0
    assert f[0] == 1.0 and np.isclose(f[1], np.percentile([1.0, 2.0, 3.0], 16))
    assert np.all(np.isinf(f[3:]))  # above the last finite order statistic: a collapse
    assert not np.isnan(f).any()
    # without collapses it is numpy's percentile exactly
    x = np.random.default_rng(1).random((9, 4))
    q = [0, 5, 33.3, 50, 84, 100]
    np.testing.assert_array_equal(fractiles(x, q), np.percentile(x, q, axis=0))
    # the median of an even count with half collapsed is inf, as np.median
    assert fractiles(np.array([[1.0], [2.0], [np.inf], [np.inf]]), [50])[0, 0] == np.inf
    with pytest.raises(ValueError, match="`q`"):
        fractiles(x, [101])


# -- records and spectra: silent NaN/inf ---------------------------------------------------


def test_huge_records_give_finite_measures_or_say_they_overflow() -> None:
    gm = GroundMotion(np.array([1e155, -1e155, 3e154, 0.0]), dt=0.01)
    assert np.isfinite(gm.significant_duration()) and gm.significant_duration() > 0
    small = GroundMotion(gm.a / 1e150, dt=0.01)  # the same shape: the same duration
    assert gm.significant_duration() == pytest.approx(small.significant_duration(), rel=1e-12)
    assert gm.arias_intensity == pytest.approx(small.arias_intensity * 1e300, rel=1e-12)
    huge = GroundMotion(np.array([1e300, -1e300, 1e300]), dt=0.01)
    with pytest.raises(ValueError, match="Arias intensity overflows"):
        _ = huge.arias_intensity
    with pytest.raises(ValueError, match="overflows"):
        huge.husid()
    assert np.isfinite(huge.significant_duration())
    top = GroundMotion(np.array([1e308, 1e308, 1e308]), dt=1.0)
    with pytest.raises(ValueError, match="velocity overflows"):
        _ = top.pgv
    with pytest.raises(ValueError, match=r"`dt`.*double range"):
        GroundMotion([0.0, 1.0, 2.0], dt=1e308)


def test_spectra_extreme_periods_and_zero_records() -> None:
    t = np.arange(0.0, 2.0, 0.01)
    a = np.sin(5.0 * t)
    with pytest.raises(ValueError, match=r"`periods`.*1e-100"):
        response_spectrum((t, a), [1e-300])
    rs = response_spectrum((t, a), [0.0, 1e-100, 1e-20])
    assert np.all(np.isfinite(rs.psa))
    np.testing.assert_allclose(rs.psa[0, 0], np.abs(a).max(), rtol=1e-6)  # rigid: the PGA
    with pytest.raises(ValueError, match=r"`motions`.*zero"):
        ductility_spectrum((t, 0.0 * a), [0.5], [2.0])
    with pytest.raises(ValueError, match="`periods` must be at least"):
        ductility_spectrum((t, a), [1e-20], [2.0])
    with pytest.raises(ValueError, match="`alpha`"):
        ductility_spectrum((t, a), [0.5], [2.0], alpha=1.0)


# -- spectra: messages and bounded memory ----------------------------------------------------


@pytest.mark.parametrize(
    ("threads", "kind"),
    [(0, ValueError), (10**6, ValueError), (True, TypeError), (-1, ValueError),
     (2**64, ValueError), (1.5, TypeError)],
)  # fmt: skip
def test_spectra_threads_are_checked_as_solve_checks_them(threads: object, kind: type) -> None:
    t = np.arange(0.0, 1.0, 0.01)
    for call in (
        lambda: response_spectrum((t, np.sin(t)), [0.5], threads=threads),
        lambda: rotd((t, np.sin(t)), (t, np.cos(t)), [0.5], threads=threads),
        lambda: ductility_spectrum((t, np.sin(t)), [0.5], [2.0], threads=threads),
    ):
        with pytest.raises(kind, match="`threads`"):
            call()


def test_rotd_refuses_huge_angle_counts_before_allocating() -> None:
    t = np.arange(0.0, 1.0, 0.01)
    with pytest.raises(ValueError, match="`n_angles`"):
        rotd((t, np.sin(t)), (t, np.cos(t)), [0.5], n_angles=10**9)
    with pytest.raises(TypeError, match="`n_angles`"):
        rotd((t, np.sin(t)), (t, np.cos(t)), [0.5], n_angles=1e9)


# -- ensembles ---------------------------------------------------------------------------


def _sdof(amplitude: float) -> duhamel.System:
    s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
    return s.add_load(duhamel.loads.Harmonic(0, amplitude=amplitude, omega=1.0))


def _with_options(amplitude: float) -> tuple[duhamel.System, dict]:
    return _sdof(amplitude), {"x0": [amplitude]}


def test_solve_many_basis_first_with_system_and_options() -> None:
    ens = solve_many(
        _with_options, [1.0, 2.0], duhamel.Semianalytic(), t_end=1.0, dt=0.1, basis="first",
        workers=1,
    )  # fmt: skip
    assert ens.stats.basis == "shared"
    one = duhamel.solve(_sdof(2.0), duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[2.0])
    np.testing.assert_allclose(ens.results[1].x, one.x, rtol=1e-12, atol=1e-15)


def test_solve_many_empty_store_and_workers_and_reduce_keys(tmp_path: pathlib.Path) -> None:
    pytest.importorskip("xarray")
    ens = solve_many(_sdof, [], duhamel.Semianalytic(), t_end=1.0, dt=0.1,
                     to_zarr=tmp_path / "e.zarr")  # fmt: skip
    assert dict(ens.to_xarray().sizes) == {"case": 0}
    with pytest.raises(TypeError, match="`workers`"):
        solve_many(_sdof, [1.0], duhamel.Semianalytic(), t_end=1.0, dt=0.1, workers=1.5)
    with pytest.raises(ValueError, match="`workers`"):
        solve_many(_sdof, [1.0], duhamel.Semianalytic(), t_end=1.0, dt=0.1, workers=0)

    def odd(sol: duhamel.Solution) -> dict:
        peak = float(np.abs(sol.x).max())
        return {"peak": peak} if peak < 1.5 else {"peak": peak, "extra": 1.0}

    ens = solve_many(_sdof, [1.0, 100.0], duhamel.Semianalytic(), t_end=5.0, dt=0.1,
                     reduce=odd, workers=1)  # fmt: skip
    with pytest.raises(ValueError, match=r"different keys.*case 1.*extra"):
        ens.to_xarray()


# -- the streaming store ---------------------------------------------------------------------


def _stored(tmp_path: pathlib.Path, name: str = "r.zarr") -> tuple[pathlib.Path, duhamel.Solution]:
    path = tmp_path / name
    s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], zeta=0.02)
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=60.0, dt=0.01, x0=[0.0, 1.0],
                        store=Store(path, segment_bytes=1))  # fmt: skip
    return path, sol


def _chunk(path: pathlib.Path, name: str, i: int) -> pathlib.Path:
    found = sorted((path / "data" / name / "c" / str(i)).rglob("*"))
    files = [f for f in found if f.is_file()]
    assert files, f"no chunk {i} of {name}"
    return files[0]


def test_store_detects_deleted_truncated_and_flipped_data_chunks(tmp_path: pathlib.Path) -> None:
    path, sol = _stored(tmp_path)
    np.testing.assert_array_equal(resume(path).x, sol.x)  # intact: read back
    for damage in ("delete", "truncate", "flip"):
        copy = tmp_path / f"{damage}.zarr"
        shutil.copytree(path, copy)
        chunk = _chunk(copy, "x", 2)
        raw = bytearray(chunk.read_bytes())
        if damage == "delete":
            chunk.unlink()
        elif damage == "truncate":
            chunk.write_bytes(bytes(raw[: len(raw) // 2]))
        else:
            raw[len(raw) // 3] ^= 0x10
            chunk.write_bytes(bytes(raw))
        with pytest.raises(StoreError, match=rf"{copy.name}.*damaged.*rows 2048:3072 of 'x'"):
            resume(copy)


def _slots(path: pathlib.Path) -> tuple:
    slots = zarr.open_group(path)["checkpoints"]
    return slots, [unpack(slots[k][...]) for k in ("0", "1")]


def test_a_damaged_checkpoint_slot_falls_back_to_the_other(tmp_path: pathlib.Path) -> None:
    path, sol = _stored(tmp_path)
    slots, (c0, c1) = _slots(path)
    newest = "0" if c0.seq > c1.seq else "1"
    files = [f for f in (path / "checkpoints" / newest).rglob("*") if f.is_file()]
    chunk = next(f for f in files if f.name != "zarr.json")
    for garbage in (b"", b"\x00" * 7, chunk.read_bytes()[:20], b"\x28\xb5\x2f\xfd" + b"x" * 50):
        copy = tmp_path / f"g{len(garbage)}.zarr"
        shutil.copytree(path, copy)
        target = copy / chunk.relative_to(path)
        target.write_bytes(garbage)
        np.testing.assert_array_equal(resume(copy).x, sol.x)  # from the older slot
    # a slot whose CRC is intact but whose numbers are forged (sealed again with the store's
    # identity) is no torn write: refused (issue 38; before, the other slot was used)
    forged = tmp_path / "forged.zarr"
    shutil.copytree(path, forged)
    slots, cps = _slots(forged)
    for k, c in zip(("0", "1"), cps, strict=True):
        for seq in (2**64 - 1, 2**63):
            slots[k][...] = pack(type(c)(**{**c.__dict__, "seq": seq}))
            with pytest.raises(StoreError, match=rf"forged\.zarr.*damaged.*'checkpoints/{k}'"):
                resume(forged)
            slots, _ = _slots(forged)
        slots[k][...] = pack(c)
    np.testing.assert_array_equal(resume(forged).x, sol.x)


def _record(path: pathlib.Path) -> tuple:
    group = zarr.open_group(path)
    return group, dict(group.attrs["duhamel"])


def test_forged_grids_and_tampered_records_are_refused(tmp_path: pathlib.Path) -> None:
    path, _ = _stored(tmp_path)
    group, record = _record(path)
    from duhamel.store._integrity import digest

    for n_steps in (10**18, -1, 1.5, "6000"):
        grid = {**record["grid"], "n_steps": n_steps}
        group.attrs["duhamel"] = {**record, "grid": grid}  # the checksum no longer matches
        with pytest.raises(StoreError, match=r"r\.zarr.*damaged.*checksum"):
            resume(path)
        # forged with its checksum written again: the grid itself is refused
        sealed = digest(grid, record["model"], group["model"], record["store"])
        forged = {**record, "grid": grid, "checksum": sealed}
        group.attrs["duhamel"] = forged
        with pytest.raises(StoreError, match=r"r\.zarr.*damaged.*n_steps"):
            resume(path)
    tree = json.loads(record["model"])
    for text in ("{not json", json.dumps({**tree, "route": 1}), record["model"][:-5]):
        group.attrs["duhamel"] = {**record, "model": text}
        with pytest.raises(StoreError, match=r"r\.zarr.*damaged"):
            resume(path)
        checksum = digest(record["grid"], text, group["model"], record["store"])
        sealed = {**record, "model": text, "checksum": checksum}
        group.attrs["duhamel"] = sealed
        with pytest.raises(StoreError, match=r"r\.zarr.*damaged"):
            resume(path)
    grid = {**record["grid"], "dofs": [99]}
    sealed = digest(grid, record["model"], group["model"], record["store"])
    group.attrs["duhamel"] = {**record, "grid": grid, "checksum": sealed}
    with pytest.raises(StoreError, match=r"damaged.*dofs"):
        resume(path)
    # a model array changed
    group.attrs["duhamel"] = record
    name = sorted(group["model"].array_keys())[0]
    arr = group["model"][name]
    arr[...] = np.asarray(arr[...]) + 1
    with pytest.raises(StoreError, match=r"r\.zarr.*damaged.*checksum"):
        resume(path)


def test_old_store_format_is_refused_clearly(tmp_path: pathlib.Path) -> None:
    path, _ = _stored(tmp_path)
    group, record = _record(path)
    group.attrs["duhamel"] = {**record, "format": 1}
    with pytest.raises(StoreError, match=r"format 1.*reads format 3.*checksums"):
        resume(path)


# -- exact references, analysis, rotors ------------------------------------------------------


def test_exact_duffing_and_transition_matrix_at_extreme_parameters() -> None:
    from duhamel import exact
    from duhamel.analysis import exact_transition_matrix

    with pytest.raises(ValueError, match=r"`b`.*`x0`.*double range"):
        exact.duffing([0.0, 1.0], 1.0, 1e300, 1e300)
    with pytest.raises(ValueError, match=r"`t`.*periods"):
        exact.duffing([0.0, 1.0], 1.0, 1e300, 1e5)  # a phase no double resolves
    # beyond b x0^2 = 1e308 with a resolvable phase: finite, and the scaled closed form
    x, v = exact.duffing([0.0, 1e-150], 0.0, 1e300, 1e5)
    assert np.all(np.isfinite(x)) and np.all(np.isfinite(v)) and x[0] == 1e5
    # the scaled computation agrees with the plain one where both work
    t = np.linspace(0.0, 3.0, 7)
    xs, _ = exact.duffing(t, 2.0, 3.0, 0.7)
    from scipy.integrate import solve_ivp

    ref = solve_ivp(lambda _t, y: [y[1], -4.0 * y[0] - 3.0 * y[0] ** 3], (0, 3), [0.7, 0.0],
                    t_eval=t, rtol=1e-12, atol=1e-14)  # fmt: skip
    np.testing.assert_allclose(xs, ref.y[0], atol=1e-9)
    s = duhamel.System([[1.0]], [[1.0]], zeta=-1000.0)
    with pytest.raises(ValueError, match=r"`dt`.*overflows"):
        exact_transition_matrix(s, dt=10.0)
    assert np.all(np.isfinite(exact_transition_matrix(s, dt=0.1)))


def test_journal_geometry_and_the_wall() -> None:
    from duhamel.rotor import ShortJournalBearing
    from duhamel.rotor.journal import JournalElement

    extreme = ShortJournalBearing(0, 0.05, 1e100, 1e-100, 0.02)
    with pytest.raises(ValueError, match=r"overflow.*`clearance`"):
        extreme.coefficients([0.0, 0.0], speed=300.0)
    b = ShortJournalBearing(0, 0.05, 0.02, 5e-5, 0.02)
    for at in ([5e-5, 0.0], [0.0, -6e-5]):
        with pytest.raises(ValueError, match=r"`position`.*wall"):
            b.coefficients(at, speed=300.0)
    # a run started at the wall stops with SolverError(reason="domain"), nothing kept
    s = duhamel.System(np.eye(2), 1e3 * np.eye(2))
    s.add(JournalElement(0, 1, 0.025, 0.02, 5e-5, 0.02, 300.0))
    with pytest.raises(duhamel.SolverError) as err:
        duhamel.solve(s, duhamel.Semianalytic(), t_end=0.1, dt=1e-3, x0=[5e-5, 0.0])
    assert err.value.reason == "domain" and err.value.partial.x.shape == (0, 2)


def _rotor() -> object:
    from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft

    return Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        [Bearing(0, 1e7, 1e7, cxx=500.0, cyy=500.0), Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)],
    )  # fmt: skip


def test_critical_speeds_on_coarse_and_huge_grids() -> None:
    rotor = _rotor()
    fine = rotor.critical_speeds(np.linspace(0.0, 1000.0, 41))
    assert fine.size == 1
    wide = rotor.critical_speeds([0.0, 1e20])
    assert np.min(np.abs(wide - fine[0])) <= 1e-9 * fine[0]  # not 0.0
    back_fine = rotor.critical_speeds(np.linspace(0.0, 1000.0, 41), whirl="backward")
    back = rotor.critical_speeds([0.0, 1000.0], whirl="backward")  # scipy's sign error before
    np.testing.assert_allclose(back, back_fine, rtol=1e-9)
    # the refined crossing is a crossing: a frequency there equals the speed
    for w in back:
        assert np.min(np.abs(rotor.modes(w).frequencies - w)) <= 1e-8 * w
    with pytest.raises(TypeError, match="`harmonic`"):
        rotor.critical_speeds([0.0, 1000.0], harmonic="1")


# -- Ctrl-C in the Rust loops of spectra and devices (a real SIGINT, in a subprocess) --------

SIGINT_SPECTRA = """
import json, os, signal, sys, threading, time
signal.signal(signal.SIGINT, signal.default_int_handler)  # even if launched with it ignored
import numpy as np
import duhamel
from duhamel.spectra import ductility_spectrum, response_spectrum, rotd

what = sys.argv[1]
rng = np.random.default_rng(0)
t = np.arange(0.0, 4000.0, 0.005)  # 800,000 samples
a = rng.standard_normal(t.size)
periods = np.logspace(-2, 1, 4000)
sent = {}

def interrupt():
    sent["t"] = time.perf_counter()
    os.kill(os.getpid(), signal.SIGINT)

threading.Timer(1.0, interrupt).start()
start = time.perf_counter()
try:
    if what == "elastic":
        response_spectrum((t, a), periods, [0.02, 0.05, 0.1])
    elif what == "rotd":
        rotd((t, a), (t, a[::-1].copy()), periods, n_angles=180)
    elif what == "ductility":
        ductility_spectrum((t[:20000], a[:20000]), periods, [2.0, 4.0])
    else:
        s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
        s.add(duhamel.elements.BoucWen(0, k=1.0, fy=0.1, n=1e6))
        s.add_load(duhamel.loads.Harmonic(0, 5.0, omega=1.0))
        duhamel.solve(s, duhamel.Semianalytic(), t_end=2e5, dt=0.01, save_every=1000)
    out = {"raised": None, "total": time.perf_counter() - start}
except KeyboardInterrupt:
    now = time.perf_counter()
    out = {"raised": "KeyboardInterrupt", "after_signal": now - sent["t"], "total": now - start}
print(json.dumps(out))
"""


def _ignore_sigint() -> None:
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


@pytest.mark.parametrize(
    ("what", "ignored"),
    [("elastic", False), ("rotd", False), ("ductility", False), ("boucwen", False),
     ("elastic", True)],
)  # fmt: skip
def test_ctrl_c_stops_spectra_and_extreme_devices(what: str, ignored: bool) -> None:
    """`ignored`: the child starts with SIGINT ignored, as under a test run launched as a
    background job (`make test &`); the script installs Python's handler itself."""
    import subprocess
    import sys

    proc = subprocess.run(
        [sys.executable, "-c", SIGINT_SPECTRA, what], capture_output=True, text=True, timeout=300,
        preexec_fn=_ignore_sigint if ignored else None,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    print(f"\n{what}: {out}")
    assert out["raised"] == "KeyboardInterrupt", out
    assert out["after_signal"] < 0.5
