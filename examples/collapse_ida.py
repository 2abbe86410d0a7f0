"""Collapse IDA of a 3-storey steel moment frame with deteriorating hinges and a leaning
P-Delta column: each record's collapse intensity (10 % storey drift, bisected to 2 % of Sa),
the lognormal collapse fragility and FEMA P695's collapse margin ratio.

The frame is a shear building (one lateral dof per floor, storey height 4 m, 4e5 kg per
floor). Each storey is

* an elastic part in ``K`` (the continuous columns, 10 % of the storey stiffness),
* its beam hinges lumped into one ``ModIMKPeakOriented`` storey spring (90 % of the storey
  stiffness, the deformation its drift, so the hinge rotation is the drift ratio) with the
  median parameters of Lignos & Krawinkler (2011), J. Struct. Eng. 137(11) 1291-1302,
  eqs. for W-sections other than RBS, evaluated for a W27x94-like beam (h/tw = 45,
  bf/2tf = 6.7, d = 683 mm, L/d = 8, Fy = 355 MPa): pre-capping plastic rotation
  ``theta_p = 0.028``, post-capping rotation ``theta_pc = 0.13``, reference cumulative
  plastic rotation ``Lambda = 1.0`` (``E_t = Lambda My``, for the strength and the
  post-capping deterioration, exponent ``c = 1``, ``D = 1``; no accelerated reloading or
  unloading-stiffness deterioration, as in their calibrations), capping strength
  ``Mc/My = 1.1``, residual strength ``0.4 My`` and ultimate rotation ``theta_u = 0.2``
  (their recommended values); yield at 1 % drift. With the columns and the leaning column
  the storeys' post-capping stiffness is -1.3 %, -0.6 % and +0.4 % of the elastic one
  (first to third); the cyclic deterioration lowers the strength further;
* a leaning column (``PDelta``) carrying the gravity of the floors above, 1.5 times the
  seismic weight (the gravity frames' share).

The records are synthetic (band-passed noise, as examples/ida.py), so nothing is downloaded;
intensity Sa(T1, 5 %); S_MT = S_M1 / T1 with S_M1 = 0.9 g (FEMA P695, SDC Dmax).

    python examples/collapse_ida.py                 # prints, shows the figure
    python examples/collapse_ida.py --save docs/figures/collapse_ida.png
    python examples/collapse_ida.py --integrator newmark --tolerance 0.002 --no-plot
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.signal

import duhamel
from duhamel.ensemble import ida
from duhamel.records import G, GroundMotion

H = 4.0  # storey height, m
MASS = 4.0e5  # kg per floor
K_STOREY = np.array([1.2e8, 1.0e8, 0.75e8])  # elastic storey stiffness, N/m
GRAVITY = 1.5  # leaning-column gravity per floor / the floor's seismic weight
LINEAR, HINGE = 0.10, 0.90  # shares of the storey stiffness
YIELD_DRIFT = 0.01  # the hinge's yield drift (My = HINGE k YIELD_DRIFT H)
# ModIMK hinge (Lignos & Krawinkler 2011, see the module docstring); rotations = drift ratios
THETA_P, THETA_PC, THETA_U = 0.028, 0.13, 0.20
LAMBDA, CAPPING, RESIDUAL = 1.0, 1.1, 0.4  # E_t = LAMBDA My (rad), Mc / My, Mr / My
COLLAPSE_DRIFT = 0.10  # FEMA P695's non-simulated collapse limit
DT = 0.01


def records(n: int = 11, seed: int = 37) -> list[GroundMotion]:
    """Synthetic records: band-passed noise, random duration and corner frequencies."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        seconds = rng.uniform(12.0, 20.0)
        t = np.arange(0.0, seconds, DT)
        lo, hi = rng.uniform(0.2, 0.6), rng.uniform(5.0, 12.0)
        b, a = scipy.signal.butter(2, [lo, hi], btype="band", fs=1 / DT)
        env = np.minimum(t / 1.5, 1.0) * np.exp(-np.maximum(t - 0.4 * seconds, 0.0) / 3.0)
        x = env * scipy.signal.lfilter(b, a, rng.normal(size=t.size))
        out.append(GroundMotion(0.3 * x / np.abs(x).max(), DT, units="g", name=f"syn{i:02d}"))
    return out


def leaning_load() -> np.ndarray:
    """The gravity each storey's leaning column carries: the floors above it, N."""
    floors = GRAVITY * MASS * G * np.ones(K_STOREY.size)
    return np.cumsum(floors[::-1])[::-1]


def storey_matrix(k: np.ndarray) -> np.ndarray:
    return np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)


def hinge(i: int, j: int | None, k: float) -> duhamel.elements.ModIMKPeakOriented:
    """The storey's hinge spring: ModIMKPeakOriented in storey displacement (m)."""
    k0 = HINGE * k
    my = k0 * YIELD_DRIFT * H
    a_s = (CAPPING - 1.0) * YIELD_DRIFT / THETA_P  # hardening to Mc at theta_p
    side = {"plus": 1.0, "neg": -1.0}
    kw = {}
    for name, sign in side.items():
        kw |= {f"as_{name}": a_s, f"My_{name}": sign * my, f"theta_p_{name}": THETA_P * H,
               f"theta_pc_{name}": THETA_PC * H, f"res_{name}": RESIDUAL,
               f"theta_u_{name}": THETA_U * H, f"D_{name}": 1.0}  # fmt: skip
    return duhamel.elements.ModIMKPeakOriented(
        i, j, K0=k0, lambda_s=LAMBDA * H, lambda_c=LAMBDA * H, lambda_a=0.0, lambda_k=0.0,
        c_s=1.0, c_c=1.0, c_a=1.0, c_k=1.0, **kw)  # fmt: skip


def frame(motion: GroundMotion | None = None) -> duhamel.System:
    """The frame (loaded by `motion` when given)."""
    s = duhamel.System(MASS * np.eye(3), storey_matrix(LINEAR * K_STOREY), zeta=0.03)
    for storey, (k, p) in enumerate(zip(K_STOREY, leaning_load(), strict=True)):
        j = None if storey == 0 else storey - 1
        s.add(duhamel.elements.PDelta(storey, j, P=p, height=H))
        s.add(hinge(storey, j, k))
    if motion is not None:
        s.add_load(motion.as_load(np.ones(3)))
    return s


def storey_drifts(x: np.ndarray) -> np.ndarray:
    """Storey drift ratios of displacement rows `x` (..., 3)."""
    return np.abs(np.diff(x, axis=-1, prepend=0.0)) / H


def peak_drift_ratio(sol: duhamel.Solution) -> float:
    return float(storey_drifts(sol.x).max())


class _MaxDrift:
    """The largest storey drift ratio minus the collapse limit (picklable)."""

    def __call__(self, t: np.ndarray, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        return storey_drifts(x).max(axis=-1) - COLLAPSE_DRIFT


def collapse_event() -> duhamel.Event:
    """Collapse: any storey reaching 10 % drift (the run stops there)."""
    return duhamel.Event(_MaxDrift(), direction=1, terminal=True, vectorized=True,
                         name="10 % storey drift")  # fmt: skip


def first_period() -> float:
    s = frame()
    k = s.K + storey_matrix(HINGE * K_STOREY)  # the hinges' initial stiffness
    w2 = np.linalg.eigvalsh(np.linalg.solve(s.M, k))
    return float(2 * np.pi / np.sqrt(w2[0]))


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="write the figure to this file")
    parser.add_argument("--records", type=int, default=11)
    parser.add_argument("--steps", type=int, default=12, help="intensities of the grid")
    parser.add_argument("--tolerance", type=float, default=0.02)
    parser.add_argument("--integrator", choices=["semianalytic", "newmark"],
                        default="semianalytic")  # fmt: skip
    parser.add_argument("--dt", type=float, help="step (default: the records' sampling)")
    parser.add_argument("--no-plot", action="store_true", help="print only")
    args = parser.parse_args(argv)
    t1 = first_period()
    s_mt = 0.9 * G / t1  # FEMA P695 SDC Dmax: S_M1 = 0.9 g, T1 > T_s
    intensities = G * np.linspace(0.25, 3.0, args.steps)
    started = time.perf_counter()
    integrator = duhamel.Newmark() if args.integrator == "newmark" else duhamel.Semianalytic()
    res = ida(frame, records(args.records), intensities, peak_drift_ratio, integrator,
              period=t1, damping=0.05, dt=args.dt, collapse=collapse_event(), solver_error="raise",
              tolerance=args.tolerance)  # fmt: skip
    seconds = time.perf_counter() - started
    frag = res.fragility(mce=s_mt)
    runs = res.measures.size + res.refinement_runs
    print(f"T1 = {t1:.3f} s; {runs} runs ({res.refinement_runs} bisection) in {seconds:.1f} s")
    print("record   collapse Sa(T1) [g]")
    for name, (lo, hi) in zip(res.names, res.collapse_brackets, strict=True):
        print(f"{name}   {hi / G:6.3f}   (no collapse at {lo / G:.3f})")
    print(f"fragility (MLE): median {frag.median / G:.3f} g, beta {frag.beta:.3f}; "
          f"S_MT = {s_mt / G:.3f} g, CMR = {frag.cmr:.2f}")  # fmt: skip
    out = {"ida": res, "fragility": frag, "t1": t1, "s_mt": s_mt, "seconds": seconds}
    if args.no_plot:
        return out
    import matplotlib

    if args.save:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    res.plot(ax1)
    ax1.axvline(COLLAPSE_DRIFT, color="C3", ls=":", lw=1)
    ax1.set_xlim(0.0, 1.2 * COLLAPSE_DRIFT)
    ax1.set_xlabel("peak storey drift ratio")
    ax1.set_ylabel(f"Sa(T1 = {t1:.2f} s) [m/s^2]")
    ax1.set_title(f"IDA, {len(res.names)} records (red: collapse intensities)")
    frag.plot(ax2, label=f"Sa(T1 = {t1:.2f} s) [m/s^2]")
    ax2.set_title("collapse fragility")
    fig.tight_layout()
    if args.save:
        fig.savefig(args.save, dpi=100, bbox_inches="tight")
    else:
        plt.show()
    return out


if __name__ == "__main__":
    main()
