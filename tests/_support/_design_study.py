"""A small isolated building and suite for the design-study tests, and the checks a study and
its report must pass (used by tests/design/test_design_study.py,
tests/design/test_report_browser.py and the example's test in tests/examples/test_examples.py)."""

from __future__ import annotations

import base64
import html.parser
import json
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

import duhamel
from duhamel.design import Building, Study
from duhamel.design.document import cell
from duhamel.design.figures import FIGURES
from duhamel.records import GroundMotion, GroundMotionPair, scale_suite
from duhamel.spectra import asce7 as asce7_spectrum

G = 9.80665
#: The tables the report must hold: the model summary, the ELF values, the suite and its
#: scaling, one per quantity per record with the statistics, the checks, reproducibility.
TABLES = (
    "table-checks",
    "table-model",
    "table-isolators",
    "table-modes",
    "table-elf",
    "table-suite",
    "table-scaling",
    "table-isolator-displacement-max",
    "table-base-shear-below",
    "table-base-shear-above",
    "table-storey-drift-ratio",
    "table-floor-acceleration",
    "table-drift-profile",
    "table-energy",
    "table-reproduce",
)
QUANTITIES = (
    "isolator_displacement",
    "isolator_displacement_max",
    "base_shear_below",
    "base_shear_above",
    "storey_drift_ratio",
    "floor_acceleration",
)


def small_building(three_d: bool = False) -> Building:
    """A base mat and three floors on two friction pendulums (uniaxial along x; or, in 3-D,
    bidirectional with the same frame along y)."""
    masses = np.array([3e5, 2e5, 2e5, 2e5])
    n = masses.size
    k1 = np.zeros((n, n))
    for s in range(1, n):
        k1[s - 1 : s + 1, s - 1 : s + 1] += 3e8 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    dirs = 2 if three_d else 1
    m = np.kron(np.eye(dirs), np.diag(masses))
    k = np.kron(np.eye(dirs), k1)
    s = duhamel.System(m, k, zeta=0.03)
    w = masses.sum() * G
    for _ in range(2):
        y = n if three_d else None
        s.add(duhamel.elements.FrictionPendulum((0, y), radius=2.0, mu=0.05, weight=w / 2))
    levels = list(range(n))
    if not three_d:
        return Building(s, levels, [3.2] * (n - 1), name="small test building")
    rx, ry = np.r_[np.ones(n), np.zeros(n)], np.r_[np.zeros(n), np.ones(n)]
    return Building(
        s, levels, [3.2] * (n - 1), x=rx, y=ry, levels_y=[n + i for i in levels], name="3-D"
    )


def pairs(count: int, duration: float = 8.0) -> list[GroundMotionPair]:
    """Seeded band-limited noise pairs with a build-up and decay, PGA 0.3 g and 0.25 g."""
    out = []
    for seed in range(count):
        rng = np.random.default_rng(500 + seed)
        t = np.arange(0.0, duration, 0.01)
        f = np.fft.rfftfreq(t.size, 0.01)
        env = np.minimum(t / 1.5, 1.0) ** 2 * np.exp(-np.maximum(t - 4.0, 0.0) / 1.5)
        comps = []
        for k, pga in enumerate((0.3, 0.25)):
            s = np.fft.rfft(rng.standard_normal(t.size))
            s[(f < 0.2) | (f > 6.0)] = 0.0
            a = np.fft.irfft(s, t.size) * env
            comps.append(GroundMotion(pga * a / np.abs(a).max(), 0.01, "g", name=f"P{seed}_{k}"))
        out.append(GroundMotionPair(*comps).map(lambda m: m.baseline_corrected()))
    return out


def small_study(count: int = 7, three_d: bool = False, duration: float = 8.0) -> Study:
    """The small building under `count` pairs scaled to an ASCE 7 MCE_R target (SDS 1.0 g,
    SD1 0.6 g) over 1.5-3.0 s, with bounds 0.8 and 1.3 on the friction."""
    target = asce7_spectrum(sds=1.0, sd1=0.6, tl=8.0, mce=True)
    scaled = scale_suite(pairs(count, duration), target, (1.5, 3.0), method="asce7")
    return Study(
        small_building(three_d),
        scaled,
        duhamel.Semianalytic(),
        dt=0.01,
        bounds={"mu": (0.8, 1.3)},
        workers=2,
        progress=False,
    )


def hand_statistics(study: Study) -> dict[str, dict[str, dict[str, Any]]]:
    """The statistics from solve_many's own results, grouped here by model and record:
    per record the larger orientation, then the mean (seven or more records) or the
    largest, the mean plus the sample standard deviation and the maximum."""
    grouped: dict[tuple[str, str], dict[str, list]] = defaultdict(lambda: defaultdict(list))
    for case, result in zip(study.ensemble.params, study.ensemble.results, strict=True):
        for key in QUANTITIES:
            grouped[(case["model"], case["record"])][key].append(np.asarray(result[key]))
    out: dict[str, dict[str, dict[str, Any]]] = {}
    for model in study.models:
        out[model] = {}
        for key in QUANTITIES:
            rows = np.array([np.max(grouped[(model, r)][key], axis=0) for r in study.suite.names])
            mean = rows.sum(axis=0) / rows.shape[0]
            sigma = np.sqrt(((rows - mean) ** 2).sum(axis=0) / (rows.shape[0] - 1))
            out[model][key] = {
                "design": mean if rows.shape[0] >= 7 else rows.max(axis=0),
                "mean": mean,
                "mean_plus_sigma": mean + sigma,
                "max": rows.max(axis=0),
            }
    return out


class Page(html.parser.HTMLParser):
    """Tables (by id: their cells' text), figures (by id: their img src) and the embedded
    JSON of a report."""

    def __init__(self) -> None:
        super().__init__()
        self.tables: dict[str, list[list[str]]] = {}
        self.figures: dict[str, str] = {}
        self.data: Any = None
        self._table: str | None = None
        self._figure: str | None = None
        self._cell: list[str] | None = None
        self._in_tbody = False
        self._script = False
        self._json = ""

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if tag == "table":
            self._table = a.get("id")
            self.tables[self._table or ""] = []
        elif tag == "tbody":
            self._in_tbody = True
        elif tag == "tr" and self._in_tbody and self._table:
            self.tables[self._table].append([])
        elif tag == "td" and self._in_tbody:
            self._cell = []
        elif tag == "figure":
            self._figure = a.get("id")
        elif tag == "img" and self._figure:
            self.figures[self._figure] = a.get("src") or ""
        elif tag == "script" and a.get("id") == "study-data":
            self._script = True

    def handle_endtag(self, tag: str) -> None:
        if tag == "td" and self._cell is not None and self._table:
            self.tables[self._table][-1].append("".join(self._cell))
            self._cell = None
        elif tag == "tbody":
            self._in_tbody = False
        elif tag == "table":
            self._table = None
        elif tag == "figure":
            self._figure = None
        elif tag == "script" and self._script:
            self._script = False
            self.data = json.loads(self._json)

    def handle_data(self, data: str) -> None:
        if self._cell is not None:
            self._cell.append(data)
        if self._script:
            self._json += data


def check_report(study: Study, html_path: Path, md_path: Path) -> Page:
    """The report parses; it holds every table and figure; each figure is an embedded PNG;
    every number printed is the embedded data's; the data is the study's (the checks, the
    statistics); the Markdown twin prints the same cells and has the figures beside it."""
    page = Page()
    page.feed(html_path.read_text(encoding="utf-8"))
    page.close()
    assert set(TABLES) <= set(page.tables), sorted(set(TABLES) - set(page.tables))
    assert set(page.figures) == set(FIGURES)
    for fid, src in page.figures.items():
        head = "data:image/png;base64,"
        assert src.startswith(head), fid
        assert base64.b64decode(src[len(head) :]).startswith(b"\x89PNG\r\n\x1a\n"), fid
    data = page.data
    assert data is not None and set(data["tables"]) == set(page.tables)
    for tid, rows in page.tables.items():
        stored = data["tables"][tid]["rows"]
        assert len(rows) == len(stored), tid
        for row, srow in zip(rows, stored, strict=True):
            for text, item in zip(row, srow, strict=True):
                want = cell(item["value"], item["unit"]) if isinstance(item, dict) else item
                assert text == want, (tid, text, want)
    # the data is the study's, exactly
    checks = study.checks
    assert len(data["checks"]) == len(checks)
    for c, d in zip(checks, data["checks"], strict=True):
        assert (d["clause"], d["value"], d["limit"], d["passes"]) == (
            c.clause,
            c.value,
            c.limit,
            c.passes,
        )
    rows = data["tables"]["table-checks"]["rows"]
    assert [r[6] for r in rows] == [c.verdict.upper() for c in checks]
    stats = study.statistics
    for tid, key in (
        ("table-isolator-displacement-max", "isolator_displacement_max"),
        ("table-base-shear-below", "base_shear_below"),
        ("table-base-shear-above", "base_shear_above"),
    ):
        design = data["tables"][tid]["rows"][-1]
        assert design[0] == "design (17.6.3.4)"
        got = [item["value"] for item in design[1:]]
        assert got == [float(stats[m][key]["design"]) for m in study.models], tid
        first = data["tables"][tid]["rows"][0][1:]
        assert [i["value"] for i in first] == [
            float(stats[m][key]["per_record"][0]) for m in study.models
        ]
    profile = data["tables"]["table-drift-profile"]["rows"]
    for k, row in enumerate(profile):
        assert [i["value"] for i in row[1:]] == [
            float(stats[m]["storey_drift_ratio"]["design"][k]) for m in study.models
        ]
    elf = data["tables"]["table-elf"]["rows"]
    assert [i["value"] for i in elf[0][1:]] == [b.d_m for b in study.elf.bounds.values()]
    # the Markdown twin: the same cells, the figures written beside it
    md = md_path.read_text(encoding="utf-8")
    for tid in ("table-checks", "table-elf", "table-isolator-displacement-max"):
        for row in page.tables[tid]:
            line = "| " + " | ".join(t.replace("|", "\\|") for t in row) + " |"
            assert line in md, (tid, line)
    folder = md_path.parent / f"{md_path.stem}_files"
    for fid in FIGURES:
        assert f"]({folder.name}/{fid}.png)" in md
        assert (folder / f"{fid}.png").read_bytes().startswith(b"\x89PNG")
    return page
