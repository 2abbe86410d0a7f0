"""An ASCE 7-22 chapter 17 design study of the isolated frame of the OpenSees example, end to
end: import, equivalent lateral force procedure, suite, bounds, checks and report.

The frame is ``examples/opensees_frame.py``'s (3 storeys, 2 bays, on two Steel01 isolators
and a flat slider, gravity applied in OpenSees first), imported with
``duhamel.opensees.from_opensees``. Then:

1. ``duhamel.design.asce7.isolated_elf``: the fixed point ``D_M``, ``T_M``, ``beta_M``,
   ``B_M``, ``k_M`` of section 17.5 from the isolators' own loops, for the nominal, lower-
   and upper-bound properties (lambda factors 0.85 and 1.3 on the isolators' strength);
2. 11 synthetic record pairs (``examples/ground_motion_suite.py``'s) scaled with
   ``scale_suite(method="asce7")`` to the MCE_R spectrum of a site with SDS = 1.0 g,
   SD1 = 0.6 g over the period range of section 17.3.3 (0.75 T_M upper to 1.25 T_M lower);
3. ``duhamel.design.Study``: each pair applied with each component along the frame in turn
   (orientations 0 and 90 degrees) on the three models, 66 runs through ``solve_many``;
   the peaks, the suite statistics and the checks of sections 17.6.4 and 16.4.1.2;
4. ``Study.report``: ``docs/asce7_isolated_study.html`` (self-contained) and its Markdown
   twin ``docs/asce7_isolated_study.md`` (figures in ``docs/asce7_isolated_study_files/``).

Usage::

    python examples/asce7_isolated_study.py                  # writes the report under docs/
    python examples/asce7_isolated_study.py --out /tmp/study.html --pairs 7 --duration 15

Needs openseespy (``pip install 'duhamel[opensees]'``), matplotlib and xarray.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import duhamel

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

#: Property modification factors (lambda_min, lambda_max) on the isolators' strength.
LAMBDA = (0.85, 1.3)
SDS, SD1, TL = 1.0, 0.6, 8.0
DT = 0.005


def frame() -> duhamel.design.Building:
    """The OpenSees example's frame, imported, as a Building: levels along x from the base
    level (above the isolators) to the roof, one dof each (the floors are tied by equalDOF)."""
    import opensees_frame as ops_frame

    ops_frame.build()
    system = duhamel.opensees.from_opensees()
    levels = [system.dof(ops_frame.node_tag(s, 0), "ux") for s in range(ops_frame.STOREYS + 1)]
    return duhamel.design.Building(
        system,
        levels,
        [ops_frame.H] * ops_frame.STOREYS,
        x="ux",
        name="3-storey frame of examples/opensees_frame.py",
    )


def lambdas(system: duhamel.System) -> dict[str, tuple[float, float]]:
    """The factors on what sets the isolators' strength: the yield force of the bilinear
    isolators (the slider is imported as one too), and the friction of friction pendulums
    when the import makes the slider one."""
    present = {n for e in system.elements for n in ("fy", "mu") if hasattr(e, n)}
    return {n: LAMBDA for n in sorted(present)}


def main(argv: list[str] | None = None) -> dict:
    from ground_motion_suite import pair

    from duhamel.design import Study, asce7
    from duhamel.records import scale_suite
    from duhamel.spectra import asce7 as asce7_spectrum

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pairs", type=int, default=11)
    parser.add_argument("--duration", type=float, default=None, help="s of each record run")
    parser.add_argument("--out", default=str(HERE.parent / "docs" / "asce7_isolated_study.html"))
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args(argv)

    started = time.perf_counter()
    building = frame()
    factors = lambdas(building.system)
    sm1 = 1.5 * SD1
    elf = asce7.isolated_elf(building, sm1=sm1, lambdas=factors, r_i=2.0)
    t_elf = time.perf_counter() - started
    print(building)
    for name, b in elf.bounds.items():
        print(
            f"ELF {name:7s}: D_M = {b.d_m:.4f} m, T_M = {b.t_m:.3f} s, beta_M = "
            f"{100 * b.beta_m:.1f} %, B_M = {b.b_m:.3f}, D_TM = {b.d_tm:.4f} m, "
            f"V_b = {b.v_b / 1e3:.1f} kN, V_s = {b.v_s / 1e3:.1f} kN"
        )

    target = asce7_spectrum(sds=SDS, sd1=SD1, tl=TL, mce=True)
    scaled = scale_suite(
        [pair(s) for s in range(args.pairs)], target, elf.period_range(), method="asce7"
    )
    print(f"scaling over {elf.period_range()[0]:.2f}-{elf.period_range()[1]:.2f} s: "
          f"lowest mean / target {scaled.table.ratio.min():.4f}")  # fmt: skip
    study = Study(
        building,
        scaled,
        duhamel.Semianalytic(),
        dt=DT,
        bounds=factors,
        t_end=args.duration,
        sm1=sm1,
        elf=elf,
        workers=args.workers,
    )
    study.run()
    print(f"{study.ensemble.stats.runs} runs in {study.wall_time['runs']:.1f} s")
    for c in study.checks:
        print(f"{c.clause:28s} {c.quantity}: {c.value:.5g} vs {c.limit:.5g} -> {c.verdict}")
    command = "python examples/asce7_isolated_study.py" + (" " + " ".join(argv) if argv else "")
    html, md = study.report(args.out, command=command)
    total = time.perf_counter() - started
    print(f"report: {html} and {md}")
    print(f"whole study {total:.1f} s (ELF {t_elf:.1f} s, runs {study.wall_time['runs']:.1f} s)")
    return {"study": study, "elf": elf, "html": html, "md": md, "seconds": total}


if __name__ == "__main__":
    main()
