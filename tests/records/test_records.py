"""Ground-motion records (issue 13): PEER .AT2 in both header styles with odd spacing, touching
fields and a partial last line, round trip against the values written; text files; the
record's exact integrals against closed forms; clear errors naming line and column."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import duhamel
from duhamel.records import G, GroundMotion, read_at2, read_text

RNG = np.random.default_rng(7)
VALUES = RNG.normal(scale=0.2, size=23)  # in g; 23 = 4 lines of 5 and a partial line of 3


def _fortran(v: float) -> str:
    """The PEER body format, E15.7 without a leading zero when negative fields touch."""
    return f"{v:15.7E}"


def write_at2(path: pathlib.Path, values: np.ndarray, style: str, per_line: int = 5) -> None:
    head = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Imperial Valley-06, 10/15/1979, El Centro Array #6, 140",
        "ACCELERATION TIME SERIES IN UNITS OF G",
    ]
    if style == "new":
        head.append(f"NPTS=   {values.size}, DT=   .0050 SEC")
    else:
        head.append(f"  {values.size}    .00500    NPTS, DT")
    body = []
    for i in range(0, values.size, per_line):
        chunk = values[i : i + per_line]
        if style == "new":
            body.append("".join(_fortran(v) for v in chunk))
        else:  # odd spacing: tabs, several blanks, plain decimals, trailing blanks
            body.append("\t ".join(f"{v:.10g}" for v in chunk) + "   ")
    path.write_text("\n".join(head + body) + "\n")


@pytest.mark.parametrize("style", ["new", "old"])
def test_at2_round_trip(tmp_path: pathlib.Path, style: str) -> None:
    p = tmp_path / "RSN6_IMPVALL.I_I-ELC180.AT2"
    write_at2(p, VALUES, style)
    gm = read_at2(p)
    fmt = _fortran if style == "new" else (lambda v: f"{v:.10g}")
    written = np.array([float(fmt(v)) for v in VALUES])
    np.testing.assert_array_equal(gm.a, written * G)
    assert gm.dt == 0.005 and gm.units == "g" and gm.name == "RSN6_IMPVALL.I_I-ELC180"
    assert gm.metadata["npts"] == 23 and "El Centro" in gm.metadata["event"]
    np.testing.assert_array_equal(gm.t, 0.005 * np.arange(23))


def test_at2_touching_fields_and_d_exponents(tmp_path: pathlib.Path) -> None:
    p = tmp_path / "x.AT2"
    p.write_text(
        "T\nE\nACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC\n4 .01 NPTS, DT\n"
        "-.1000E+02-.2500D+01\n  3.5  +4\n"
    )
    gm = read_at2(p)
    np.testing.assert_array_equal(gm.a, np.array([-10.0, -2.5, 3.5, 4.0]) * 0.01)
    assert gm.units == "cm/s^2"


def test_at2_errors_name_line_and_column(tmp_path: pathlib.Path) -> None:
    p = tmp_path / "bad.AT2"
    p.write_text("T\nE\nACCELERATION IN UNITS OF G\nNPTS= 4, DT= .01 SEC\n 0.1 0.2\n 0.3 x0.4\n")
    with pytest.raises(ValueError, match=r"line 6, column 6: expected a number, got 'x0.4'"):
        read_at2(p)
    p.write_text("T\nE\nACCELERATION IN UNITS OF G\nNPTS= 5, DT= .01 SEC\n 0.1 0.2\n 0.3 0.4\n")
    with pytest.raises(ValueError, match="NPTS = 5 values, the file has 4"):
        read_at2(p)
    p.write_text("T\nE\nACCELERATION IN UNITS OF G\nPOINTS 5\n 0.1\n")
    with pytest.raises(ValueError, match="line 4: expected 'NPTS="):
        read_at2(p)
    p.write_text("T\nE\nVELOCITY TIME SERIES IN UNITS OF CM/S\nNPTS= 1, DT= .01 SEC\n 0.1\n")
    with pytest.raises(ValueError, match="not an acceleration record"):
        read_at2(p)
    p.write_text("T\nE\nACCELERATION TIME SERIES\nNPTS= 2, DT= .01 SEC\n 0.1 0.2\n")
    with pytest.raises(ValueError, match="pass `units`"):
        read_at2(p)
    assert read_at2(p, units="g").pga == pytest.approx(0.2 * G, rel=1e-15)


def test_text_layouts(tmp_path: pathlib.Path) -> None:
    p = tmp_path / "one.txt"
    p.write_text("# header\n\n" + "\n".join(repr(float(v)) for v in VALUES) + "\n")
    np.testing.assert_array_equal(read_text(p, dt=0.01, units="g").a, VALUES * G)
    p = tmp_path / "two.csv"
    t = 0.02 * np.arange(VALUES.size)
    p.write_text(
        "time, acc\n"
        + "\n".join(f"{float(a)!r}, {float(b)!r}" for a, b in zip(t, VALUES, strict=True))
        + "\n"
    )
    gm = read_text(p, time_column=0, units="m/s^2", skip_rows=1)
    assert gm.dt == pytest.approx(0.02, rel=1e-14)
    np.testing.assert_array_equal(gm.a, VALUES)
    p = tmp_path / "flat.txt"
    p.write_text(
        "\n".join(" ".join(repr(float(v)) for v in VALUES[i : i + 4]) for i in range(0, 23, 4))
    )
    np.testing.assert_array_equal(read_text(p, dt=0.01, units="gal", flatten=True).a, VALUES * 0.01)
    p = tmp_path / "three.txt"
    p.write_text("0 1 2\n0.01 3 4\n")
    with pytest.raises(ValueError, match="pass `column`"):
        read_text(p, time_column=0, units="g")
    assert read_text(p, time_column=0, column=2, units="g").a[1] == 4 * G
    p.write_text("0 1\n0.01 3 4\n")
    with pytest.raises(ValueError, match="line 2: 3 columns where the first data line"):
        read_text(p, dt=0.01, column=0, units="g")
    p.write_text("0 1\n0.01 3\n0.03 4\n")
    with pytest.raises(
        ValueError, match=r"line 3: time step 0\.02 s differs from the first step 0\.01 s"
    ):
        read_text(p, time_column=0, units="g")
    with pytest.raises(ValueError, match="`units` must be one of"):
        read_text(p, time_column=0, units="furlong/fortnight^2")
    with pytest.raises(ValueError, match="exactly one of `dt` and `time_column`"):
        read_text(p, units="g")


def test_exact_integrals_of_the_piecewise_linear_record() -> None:
    """a = sin(w t) sampled: velocity and displacement are the exact integrals of the
    piecewise-linear interpolant; against a fine trapezoid of that interpolant."""
    dt, n, w = 0.01, 401, 7.0
    gm = GroundMotion(np.sin(w * dt * np.arange(n)), dt)
    fine = np.linspace(0.0, gm.duration, 100 * (n - 1) + 1)
    a = np.interp(fine, gm.t, gm.a)
    h = fine[1] - fine[0]
    v = np.concatenate([[0.0], np.cumsum(0.5 * h * (a[1:] + a[:-1]))])
    d = np.concatenate([[0.0], np.cumsum(0.5 * h * (v[1:] + v[:-1]))])
    np.testing.assert_allclose(gm.velocity, v[::100], atol=1e-12)
    np.testing.assert_allclose(gm.displacement, d[::100], atol=5e-6 * np.abs(d).max())
    # Arias: pi/(2g) * integral of the interpolant squared, exactly per segment
    a0, a1 = gm.a[:-1], gm.a[1:]
    ref = (
        np.pi / (2 * G) * sum(dt * (x * x + x * y + y * y) / 3 for x, y in zip(a0, a1, strict=True))
    )
    assert gm.arias_intensity == pytest.approx(ref, rel=1e-13)
    # a constant record: Arias linear in time, D5-95 = 0.9 duration, D5-75 = 0.7 duration
    flat = GroundMotion(np.full(1001, 2.0), 0.01)
    assert flat.arias_intensity == pytest.approx(np.pi / (2 * G) * 4.0 * 10.0, rel=1e-13)
    assert flat.significant_duration() == pytest.approx(9.0, rel=1e-12)
    assert flat.significant_duration(0.05, 0.75) == pytest.approx(7.0, rel=1e-12)


def test_scaling_load_and_errors() -> None:
    gm = GroundMotion([0.0, 0.3, -0.1, 0.0], dt=0.01, units="g", name="r", metadata={"k": 1})
    s = gm.scaled(2.5).scaled(2.0)
    np.testing.assert_array_equal(s.a, gm.a * 5.0)
    assert s.metadata == {"k": 1, "scale": 5.0} and s.name == "r"
    load = gm.as_load(np.ones(2))
    assert isinstance(load, duhamel.loads.BaseAcceleration)
    np.testing.assert_array_equal(load.values, gm.a)
    with pytest.raises(ValueError, match="`dt`"):
        GroundMotion([0.0, 1.0], dt=0.0)
    with pytest.raises(ValueError, match="`a`"):
        GroundMotion([0.0, np.nan], dt=0.01)
    with pytest.raises(ValueError, match="`a` must have at least 2"):
        GroundMotion([1.0], dt=0.01)
    with pytest.raises(ValueError, match="`factor`"):
        gm.scaled(np.inf)
    with pytest.raises(ValueError, match="is zero"):
        GroundMotion(np.zeros(3), 0.01).significant_duration()


def test_base_excited_sdof_from_a_record_matches_its_velocity() -> None:
    """A record drives a System: the relative response of a very flexible oscillator is
    minus the ground displacement (it stays in place), an end-to-end check of units."""
    dt = 0.005
    t = dt * np.arange(2001)
    gm = GroundMotion(0.3 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.3 * t), dt, units="g")
    s = duhamel.System(np.eye(1), np.array([[1e-12]])).add_load(gm.as_load(np.ones(1)))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=gm.duration, dt=dt)
    np.testing.assert_allclose(sol.x[:, 0], -gm.displacement, atol=1e-9 * gm.pgd)
