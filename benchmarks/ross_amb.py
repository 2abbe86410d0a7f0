"""The unbalance response of ROSS's magnetic-bearing rotor against ROSS's own (issue 40).

``ross.rotor_amb_example()`` (212 lateral dofs, two magnetic bearings with PD controllers)
with a stable PID (``kp = 1100``, ``ki = 400``), 60 speeds 50-3000 rad/s, an unbalance of
1e-4 kg m at the disk of node 27: ROSS's ``run_unbalance_response`` (its bearings' equivalent
coefficients at each speed, interpolated by its spline) against duhamel's
``from_ross(...).rotor.unbalance_response`` (the closed loop's steady state: each bearing's
dynamic stiffness ``k_i C(i w) - k_s`` at the speed). Contenders interleaved, best and median
of the repeats, the models made outside the timed calls (duhamel's ``model.rotor`` fresh in
each call; ROSS's ``run_modal`` cache cleared).

Usage::

    python benchmarks/ross_amb.py                          # print
    python benchmarks/ross_amb.py --append BENCHMARKS.md   # as a section
    python benchmarks/ross_amb.py --quick                  # 1 repeat
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import contextlib  # noqa: E402
import datetime  # noqa: E402
import io  # noqa: E402
import statistics  # noqa: E402
import warnings  # noqa: E402

import _section  # noqa: E402
import numpy as np  # noqa: E402

SPEEDS = np.linspace(50.0, 3000.0, 60)


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def stable_amb_rotor():
    ross = quiet(__import__, "ross")
    base = quiet(ross.rotor_amb_example)
    bearings = []
    for b in base.bearing_elements:
        f = lambda v: float(np.asarray(v).ravel()[0])  # noqa: E731
        bearings.append(
            quiet(
                ross.MagneticBearingElement,
                n=b.n,
                g0=f(b.g0),
                i0=f(b.i0),
                ag=f(b.ag),
                nw=f(b.nw),
                alpha=f(b.alpha),
                kp_pid=1100.0,
                kd_pid=f(b.kd_pid),
                ki_pid=400.0,
                n_f=f(b.n_f),
            )
        )
    return quiet(ross.Rotor, base.shaft_elements, base.disk_elements, bearings)


def measure(repeats: int) -> dict:
    from duhamel.rotor import from_ross

    rr = stable_amb_rotor()
    model = from_ross(rr, 0.0)
    out: dict = {}
    times: dict[str, list[float]] = {"ross": [], "duhamel": []}
    load0 = os.getloadavg()[0]
    for _ in range(repeats):
        times["ross"].append(_section.timed(lambda: out.update(ross=quiet(
            rr.run_unbalance_response, 27, 1e-4, 0.0, SPEEDS).forced_resp.T)))  # fmt: skip
        times["duhamel"].append(_section.timed(lambda: out.update(duhamel=(
            model.rotor.unbalance_response(SPEEDS, [(27, 1e-4, 0.0)]).response))))  # fmt: skip
    lateral = model.dofs.ross_index
    ours = model.dofs.to_ross(out["duhamel"])[:, lateral]
    theirs = out["ross"][:, lateral]
    err = float(np.abs(ours - theirs).max() / np.abs(theirs).max())
    return {"times": times, "error": err, "load": (load0, os.getloadavg()[0]),
            "repeats": repeats}  # fmt: skip


def markdown(r: dict) -> list[str]:
    t = r["times"]
    best = {k: min(v) for k, v in t.items()}
    med = {k: statistics.median(v) for k, v in t.items()}
    return [
        "## Magnetic-bearing rotor: unbalance response against ROSS (issue 40)",
        "",
        f"`python benchmarks/ross_amb.py --append BENCHMARKS.md` "
        f"({datetime.date.today().isoformat()}), one core, {r['repeats']} interleaved "
        f"repeats; 1-min load average before {r['load'][0]:.2f}, after {r['load'][1]:.2f}. "
        "ROSS's `rotor_amb_example` with a stable PID, 60 speeds; the difference is ROSS's "
        "smoothing spline through its bearings' coefficient table "
        "(tests/rotor/test_ross_magnetic.py: on the spline's coefficients the two agree to 1e-8).",
        "",
        "| ROSS best / median [s] | duhamel best / median [s] | ratio (best) | difference |",
        "|---:|---:|---:|---:|",
        f"| {best['ross']:.3f} / {med['ross']:.3f} | {best['duhamel']:.3f} / "
        f"{med['duhamel']:.3f} | {best['ross'] / best['duhamel']:.1f}x | {r['error']:.1e} |",
    ]


def main(argv: list[str] | None = None) -> int:
    return _section.main(
        __doc__, lambda quick: markdown(measure(1 if quick else 3)), "1 repeat", argv
    )


if __name__ == "__main__":
    raise SystemExit(main())
