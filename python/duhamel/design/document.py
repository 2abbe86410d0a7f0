"""The content of a study's report as plain data (:func:`document`): sections of paragraphs,
tables and figures, every number kept with its unit beside the text it is printed as
(:func:`cell`), so that the HTML, the Markdown and the embedded data say the same."""

from __future__ import annotations

import platform
import sys
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from duhamel.constants import STANDARD_GRAVITY
from duhamel.design.figures import FIGURES

__all__ = ["FORMATS", "Section", "Table", "cell", "document"]

#: How a value in SI units is printed, per display unit: (factor from SI, format).
FORMATS: dict[str, tuple[float, str]] = {
    "m": (1.0, "{:.4f}"),
    "kN": (1e-3, "{:.1f}"),
    "kN/m": (1e-3, "{:.1f}"),
    "kJ": (1e-3, "{:.1f}"),
    "%": (100.0, "{:.3f}"),
    "g": (1.0 / STANDARD_GRAVITY, "{:.3f}"),
    "s": (1.0, "{:.3f}"),
    "": (1.0, "{:.4g}"),
}


def cell(value: float, unit: str) -> str:
    """`value` (SI) as the report prints it in `unit` (:data:`FORMATS`)."""
    factor, form = FORMATS[unit]
    return form.format(factor * float(value))


@dataclass
class Table:
    """A table: each row's cells are text or ``(value, unit)`` pairs (printed by
    :func:`cell`, kept as numbers in the report's data)."""

    id: str
    caption: str
    header: list[str]
    rows: list[list[Any]] = field(default_factory=list)


@dataclass
class Section:
    id: str
    title: str
    paragraphs: list[str] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    figures: list[str] = field(default_factory=list)


def _checks(study: Any) -> Section:
    units = {"m": "m", "N": "kN", "": ""}
    rows = []
    for c in study.checks:
        u = "%" if "drift" in c.quantity else units.get(c.units, "")
        rows.append(
            [
                c.clause,
                c.quantity,
                u,
                (c.value, u),
                (c.limit, u),
                (c.ratio, ""),
                c.verdict.upper(),
                c.note,
            ]
        )
    passed = sum(c.passes for c in study.checks)
    intro = (
        f"{passed} of {len(study.checks)} checks pass. A lower limit (kind 'minimum') that "
        "fails means the response-history values are scaled up to it (section 17.6.4.3)."
    )
    table = Table(
        "table-checks",
        "Code checks (design values: the suite's, on the governing model)",
        ["clause", "quantity", "unit", "value", "limit", "ratio", "verdict", "how"],
        rows,
    )
    return Section("checks", "Code checks", [intro], [table])


def _model(study: Any) -> Section:
    from duhamel.design import summary

    b, elf = study.building, study.elf
    s = b.system
    model = Table(
        "table-model",
        "The model",
        ["property", "value"],
        [
            ["name", b.name],
            ["degrees of freedom", str(s.n_dof)],
            ["levels (base level first)", str(len(b.levels))],
            ["storey heights", ", ".join(f"{h:g}" for h in b.heights) + " m"],
            ["seismic weight W [kN]", (b.weight, "kN")],
            ["weight above the base level W_s [kN]", (b.weight_above, "kN")],
            ["damping as stated", summary.damping(s)],
            ["isolators", str(len(b.isolators))],
            ["integrator", repr(study.integrator)],
            ["time step [s]", (study.dt, "s")],
            ["duration [s]", (study.t_end, "s")],
        ],
    )
    nominal = elf.bounds["nominal"]
    iso = Table(
        "table-isolators",
        f"The isolators and their effective properties at the nominal D_M = "
        f"{cell(nominal.d_m, 'm')} m (from their own loops)",
        ["element", "definition", "k_eff [kN/m]", "beta_eff [%]"],
        [
            [str(i), repr(e), (p.stiffness, "kN/m"), (p.damping, "%")]
            for i, e, p in zip(b.isolators, b.isolator_elements, nominal.isolators, strict=True)
        ],
    )
    modes = Table(
        "table-modes",
        "Modes: isolators at their initial stiffness (periods and damping as integrated) and "
        "at their nominal effective stiffness at D_M (periods, x participation)",
        ["mode", "T initial [s]", "zeta [%]", "T effective [s]", "mass ratio x [%]",
         "cumulative [%]"],
        [
            [str(i + 1), (m["period_initial"], "s"), (m["zeta"], "%"),
             (m["period_effective"], "s"), (m["ratio"], "%"), (m["cumulative"], "%")]
            for i, m in enumerate(summary.modes(study))
        ],
    )  # fmt: skip
    return Section("model", "Model", [], [model, iso, modes])


def _elf(study: Any) -> Section:
    elf = study.elf
    names = list(elf.bounds)
    rows_spec = [
        ("D_M (Eq. 17.5-1)", "d_m", "m"),
        ("T_M (Eq. 17.5-2)", "t_m", "s"),
        ("beta_M", "beta_m", "%"),
        ("B_M (Table 17.5-1)", "b_m", ""),
        ("k_M", "k_m", "kN/m"),
        ("D_TM (Eq. 17.5-3)", "d_tm", "m"),
        ("V_b (Eq. 17.5-5)", "v_b", "kN"),
        ("V_st (Eq. 17.5-7)", "v_st", "kN"),
        ("V_s (Eq. 17.5-6, 17.5.4.3)", "v_s", "kN"),
        ("activation force", "activation", "kN"),
    ]
    rows = [[label] + [(getattr(elf.bounds[n], a), u) for n in names] for label, a, u in rows_spec]
    table = Table(
        "table-elf",
        f"Equivalent lateral force procedure (section 17.5), S_M1 = {elf.sm1:g} g, "
        f"R_I = {elf.r_i:g}",
        ["quantity"] + [f"{n} properties" for n in names],
        rows,
    )
    lo, hi = elf.period_range()
    scaling = f"Scaling range of section 17.3.3: {lo:.3f}-{hi:.3f} s (0.75 T_M upper to "
    text = [scaling + "1.25 T_M lower).", *elf.notes]
    return Section("elf", "Equivalent lateral force procedure", text, [table])


def _suite(study: Any) -> Section:
    suite = study.suite
    rows = []
    for name, r, f in zip(suite.names, suite.records, suite.factors, strict=True):
        comps = (r.first, r.second) if hasattr(r, "first") else (r,)
        pga = [(f * c.pga, "g") for c in comps] + ([] if len(comps) == 2 else ["-"])
        rows.append([name, (f, ""), *pga])
    tables = [
        Table("table-suite", "The records and their factors (PGA of the scaled components)",
              ["record", "factor", "PGA first [g]", "PGA second [g]"], rows)
    ]  # fmt: skip
    angles = " and ".join(f"{a:g}" for a in study.orientations)
    text = [f"{len(suite)} records, each applied at {angles} degrees."]
    if study.scaled is not None:
        t = study.scaled.table
        pick = np.unique(np.linspace(0, t.period.size - 1, 12).round().astype(int))
        tables.append(
            Table(
                "table-scaling",
                f"Scaling ({study.scaled.method}): the suite mean against the target",
                ["T [s]", "target [g]", "mean [g]", "mean / target"],
                [
                    [
                        (t.period[i], "s"),
                        (t.target[i], "g"),
                        (t.mean[i], "g"),
                        (t.mean[i] / t.target[i], ""),
                    ]
                    for i in pick
                ],
            )
        )
        text.append(f"Target: {study.scaled.target.name}.")
    return Section("suite", "Suite and scaling", text, tables, ["figure-spectra"])


PEAK_TABLES = (
    ("isolator_displacement_max", "Isolator displacement, largest isolator", "m"),
    ("base_shear_below", "Shear below the isolation interface (through the isolators)", "kN"),
    ("base_shear_above", "Shear above the base level (first storey)", "kN"),
    ("storey_drift_ratio", "Storey drift ratio, largest storey", "%"),
    ("floor_acceleration", "Absolute floor acceleration, largest level", "g"),
)


def _peaks(study: Any) -> Section:
    stats = study.statistics
    models = list(stats)
    tables = []
    for key, title, unit in PEAK_TABLES:
        per = {m: stats[m][key]["per_record"] for m in models}
        per = {m: v if v.ndim == 1 else v.max(axis=1) for m, v in per.items()}
        rows = [
            [name] + [(per[m][r], unit) for m in models] for r, name in enumerate(study.suite.names)
        ]
        from duhamel.design.asce7.history import suite_value

        for label, fn in (
            ("mean", lambda v: v.mean()),
            ("mean + sigma", lambda v: v.mean() + (v.std(ddof=1) if v.size > 1 else 0.0)),
            ("max", lambda v: v.max()),
            ("design (17.6.3.4)", lambda v: suite_value(v)),
        ):
            rows.append([label] + [(float(fn(per[m])), unit) for m in models])
        tables.append(
            Table(
                f"table-{key.replace('_', '-')}",
                f"{title} [{unit}] per record (the larger orientation) and over the suite",
                ["record"] + [f"{m} properties" for m in models],
                rows,
            )
        )
    profile = [
        [str(k + 1)] + [(stats[m]["storey_drift_ratio"]["design"][k], "%") for m in models]
        for k in range(len(study.building.heights))
    ]
    tables.append(
        Table("table-drift-profile", "Storey drift ratio [%] per storey, suite design value",
              ["storey"] + [f"{m} properties" for m in models], profile)
    )  # fmt: skip
    ds = study.dataset
    m = models.index("nominal")
    rows = []
    for r, name in enumerate(study.suite.names):
        o = int(np.argmax(ds["energy_input"].values[m, r]))
        rows.append(
            [name]
            + [(float(ds[k].values[m, r, o]), "kJ") for k in
               ("energy_input", "energy_damping", "energy_hysteretic")]
            + [(float(ds["energy_error"].values[m, r, o]), "%")]
            + [(float(ds[k].values[m, r, o]), "%") for k in ("error_estimate", "error_bound")]
        )  # fmt: skip
    tables.append(
        Table("table-energy", "Energy at the end of each record (nominal properties, the "
              "orientation with more input): input, dissipated, balance error of the run; "
              "the time step's estimated error and its bound (docs/accuracy.md), the worst "
              "of the saved dofs and the elements, relative to their peaks",
              ["record", "input [kJ]", "damping [kJ]", "hysteretic [kJ]", "error [% of input]",
               "step error estimate [% of peak]", "step error bound [% of peak]"],
              rows)
    )  # fmt: skip
    return Section("peaks", "Peak responses per record", [], tables)


def _figures(study: Any) -> Section:
    ids = [k for k in FIGURES if k != "figure-spectra"]
    return Section("figures", "Figures", [], [], ids)


def _reproduce(study: Any, command: str) -> Section:
    import numpy
    import scipy

    import duhamel
    from duhamel.design import summary

    digest = summary.digests(study)
    stats = study.ensemble.stats
    rows = [
        ["duhamel", duhamel.__version__],
        ["python, numpy, scipy", f"{sys.version.split()[0]}, {numpy.__version__}, "
         f"{scipy.__version__}"],
        ["platform", platform.platform()],
        ["date (UTC)", time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime())],
        ["command", command],
        ["model digest (sha256)", digest["model"]],
        ["records digest (sha256)", digest["records"]],
        ["settings digest (sha256)", digest["settings"]],
        ["runs", f"{stats.runs} on {stats.workers} {stats.where} in "
         f"{study.wall_time.get('runs', 0.0):.1f} s"],
        ["standard gravity", f"{STANDARD_GRAVITY} m/s^2"],
    ]  # fmt: skip
    table = Table("table-reproduce", "How this report was made", ["item", "value"], rows)
    return Section("reproduce", "Reproducibility", [], [table])


def document(study: Any, command: str) -> list[Section]:
    """The report's sections, in order."""
    return [
        _checks(study),
        _model(study),
        _elf(study),
        _suite(study),
        _peaks(study),
        _figures(study),
        _reproduce(study, command),
    ]
