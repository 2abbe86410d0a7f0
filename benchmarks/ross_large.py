"""Large rotors against ROSS (issue 40): ROSS's compressor (224 lateral dofs, 14 seals and
bearings with frequency-dependent coefficients), its lowest modes, Campbell diagram, Level I
and critical speeds.

Contenders interleaved in one run (best and median of the repeats), each on a model made
once outside the timed call (duhamel: ``from_ross(...)``, a fresh ``model.rotor`` in each
call so that nothing cached from a previous call is reused; ROSS: its ``Rotor``, the cache
of its ``run_modal`` cleared before each call):

* lowest 12 modes at 1050 rad/s: ``rotor.modes(1050, n=12)`` against ROSS's
  ``run_modal(1050, num_modes=24)`` (its 24 eigenvalues are the 12 modes and their
  conjugates);
* Campbell diagram over 16 speeds 0-1500 rad/s, 8 modes: ``rotor.campbell(speeds,
  n_modes=8)`` against ``run_campbell(speeds, frequencies=8)``;
* Level I at 1050 rad/s, cross-coupling at node 25, 5 values 0-1e7 N/m: ROSS's
  ``run_level1(n=25, stiffness_range=(0, 1e7), num=5)`` (``rated_w`` 1050) against
  ``rotor.level1_stability(1050, location=25, q_range=np.linspace(0, 1e7, 5))`` (which also
  refines the threshold when it is within the range);
* critical speeds over 30 speeds 50-1500 rad/s (the forward ones, each with its
  amplification factor from the unbalance response): duhamel only, against the issue's
  target of 2 s.

The answers are compared with the dense (QZ) path of duhamel (``SPARSE_DOFS`` raised) and,
for the modes, with ROSS's eigenvalues.

Usage::

    python benchmarks/ross_large.py                          # print
    python benchmarks/ross_large.py --append BENCHMARKS.md   # as a section
    python benchmarks/ross_large.py --quick                  # 1 repeat
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

SPEED = 1050.0
CAMPBELL = np.linspace(0.0, 1500.0, 16)
Q = np.linspace(0.0, 1e7, 5)
CRITICAL = np.linspace(50.0, 1500.0, 30)


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def measure(repeats: int) -> dict:
    import duhamel.rotor._sparse_modes as sparse

    ross = quiet(__import__, "ross")
    from duhamel.rotor import from_ross

    rr = quiet(ross.compressor_example)
    rr.rated_w = SPEED
    model = from_ross(rr, 0.0)
    out: dict = {}

    def fresh(fn, *args, **kwargs):  # ROSS keeps run_modal's results per instance
        rr.run_modal.cache_clear()
        return quiet(fn, *args, **kwargs)

    pairs = {
        "lowest 12 modes at 1050 rad/s": (
            lambda: fresh(rr.run_modal, SPEED, num_modes=24),
            lambda: model.rotor.modes(SPEED, n=12),
        ),
        "Campbell, 16 speeds, 8 modes": (
            lambda: fresh(rr.run_campbell, CAMPBELL, frequencies=8),
            lambda: model.rotor.campbell(CAMPBELL, n_modes=8),
        ),
        "Level I, 5 cross-couplings": (
            lambda: fresh(rr.run_level1, n=25, stiffness_range=(0.0, 1e7), num=5),
            lambda: quiet(model.rotor.level1_stability, SPEED, location=25, q_range=Q),
        ),
        "critical speeds, 30 speeds (with AF)": (
            None,
            lambda: model.rotor.critical_speeds(CRITICAL),
        ),
    }
    load0 = os.getloadavg()[0]
    times: dict[str, dict[str, list[float]]] = {k: {"ross": [], "duhamel": []} for k in pairs}
    quiet(rr.run_modal, SPEED, num_modes=24)  # ROSS's first call compiles (numba)
    for _ in range(repeats):
        for name, (theirs, ours) in pairs.items():
            if theirs is not None:
                times[name]["ross"].append(_section.timed(lambda t=theirs, n=name: out.update(
                    {n + " ross": t()})))  # fmt: skip
            times[name]["duhamel"].append(_section.timed(lambda o=ours, n=name: out.update(
                {n: o()})))  # fmt: skip
    load1 = os.getloadavg()[0]
    # the answers: against the dense path, and the modes against ROSS's eigenvalues
    modes = out["lowest 12 modes at 1050 rad/s"]
    lam = np.asarray(out["lowest 12 modes at 1050 rad/s ross"].evalues)
    ross_err = max(float(np.min(np.abs(lam - m)) / abs(m)) for m in modes.eigenvalues)
    saved = sparse.SPARSE_DOFS
    sparse.SPARSE_DOFS = 10**9
    try:
        dense_modes = model.rotor.modes(SPEED, n=12)
        dense_camp = model.rotor.campbell(CAMPBELL, n_modes=8)
        dense_l1 = quiet(model.rotor.level1_stability, SPEED, location=25, q_range=Q)
        dense_crit = model.rotor.critical_speeds(CRITICAL)
    finally:
        sparse.SPARSE_DOFS = saved
    camp = out["Campbell, 16 speeds, 8 modes"]
    l1 = out["Level I, 5 cross-couplings"]
    crit = out["critical speeds, 30 speeds (with AF)"]
    errors = {
        "lowest 12 modes at 1050 rad/s": float(
            np.abs(modes.eigenvalues - dense_modes.eigenvalues).max()
            / np.abs(dense_modes.eigenvalues).max()
        ),
        "Campbell, 16 speeds, 8 modes": float(
            np.nanmax(np.abs(camp.frequencies - dense_camp.frequencies) / dense_camp.frequencies)
        ),
        "Level I, 5 cross-couplings": float(
            np.abs(l1.log_dec - dense_l1.log_dec).max() / np.abs(dense_l1.log_dec).max()
        ),
        "critical speeds, 30 speeds (with AF)": float(
            np.abs(crit.speeds - dense_crit.speeds).max() / crit.speeds.max()
        )
        if crit.size == dense_crit.size
        else float("inf"),
    }
    return {"times": times, "errors": errors, "ross_err": ross_err, "load": (load0, load1),
            "repeats": repeats, "critical": crit.speeds.tolist()}  # fmt: skip


def markdown(r: dict) -> list[str]:
    today = datetime.date.today().isoformat()
    lines = [
        "## Large rotors against ROSS: the compressor's modes, Campbell, Level I, critical "
        "speeds (issue 40)",
        "",
        f"`python benchmarks/ross_large.py --append BENCHMARKS.md` ({today}), one core, "
        f"{r['repeats']} interleaved repeats; 1-min load average before {r['load'][0]:.2f}, "
        f"after {r['load'][1]:.2f}. duhamel's lowest modes by shift-invert Arnoldi on the "
        "first-order pencil (`duhamel.rotor._sparse_modes`), ROSS's matrices per speed from "
        "its bearings' curves (`duhamel.rotor.ross.coefficients`). Largest difference from "
        "duhamel's dense QZ path in the last column (the modes against ROSS's own eigenvalues: "
        f"{r['ross_err']:.1e}). Critical speeds found: "
        + ", ".join(f"{w:.2f}" for w in r["critical"])
        + " rad/s.",
        "",
        "| analysis | ROSS best / median [s] | duhamel best / median [s] | ratio (best) | "
        "difference from the dense path |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, t in r["times"].items():
        d = (min(t["duhamel"]), statistics.median(t["duhamel"]))
        if t["ross"]:
            o = (min(t["ross"]), statistics.median(t["ross"]))
            ross, ratio = f"{o[0]:.3f} / {o[1]:.3f}", f"{o[0] / d[0]:.1f}x"
        else:
            ross, ratio = "—", "—"
        lines.append(
            f"| {name} | {ross} | {d[0]:.3f} / {d[1]:.3f} | {ratio} | {r['errors'][name]:.1e} |"
        )
    return lines


def main(argv: list[str] | None = None) -> int:
    return _section.main(
        __doc__, lambda quick: markdown(measure(1 if quick else 3)), "1 repeat", argv
    )


if __name__ == "__main__":
    raise SystemExit(main())
