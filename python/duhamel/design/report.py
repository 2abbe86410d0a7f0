"""A study's report (:func:`write_report`): one self-contained HTML file (styles inline,
figures embedded as PNG data, the numbers also as JSON in ``<script id="study-data">``)
and its Markdown twin with the figures beside it. Opens offline in any browser."""

from __future__ import annotations

import base64
import html
import json
import shlex
import sys
from pathlib import Path
from typing import Any

from duhamel.design.document import Section, Table, cell, document
from duhamel.design.figures import FIGURES, figures

__all__ = ["write_report"]

STYLE = """
body { font-family: -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 1.5em auto;
       max-width: 72em; padding: 0 1em; color: #1b1b1b; line-height: 1.4; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; }
p.meta { color: #555; margin-top: 0; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.9em; }
caption { text-align: left; font-weight: 600; padding-bottom: 0.3em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }
th { background: #f0f0f0; } td.text { text-align: left; }
td.pass { background: #dff3df; font-weight: 600; text-align: center; }
td.fail { background: #f8d7d7; font-weight: 600; text-align: center; }
figure { margin: 1em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { color: #444; font-size: 0.9em; }
"""


def _value(item: Any) -> Any:
    """A cell's data: the number (SI) and its display unit, or the text."""
    if isinstance(item, tuple):
        return {"value": float(item[0]), "unit": item[1]}
    return str(item)


def _text(item: Any) -> str:
    return cell(*item) if isinstance(item, tuple) else str(item)


def _html_table(t: Table) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in t.header)
    body = []
    for row in t.rows:
        cells = []
        for item in row:
            text = _text(item)
            if text in ("PASS", "FAIL"):
                cls = text.lower()
            else:
                cls = "text" if not isinstance(item, tuple) else "num"
            cells.append(f'<td class="{cls}">{html.escape(text)}</td>')
        body.append("<tr>" + "".join(cells) + "</tr>")
    return (
        f'<table id="{t.id}"><caption>{html.escape(t.caption)}</caption>'
        f"<thead><tr>{head}</tr></thead><tbody>\n" + "\n".join(body) + "\n</tbody></table>"
    )


def _html(title: str, meta: str, sections: list[Section], pngs: dict[str, bytes], data: Any) -> str:
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f'<p class="meta">{html.escape(meta)}</p>',
    ]
    for number, s in enumerate(sections, start=1):
        parts.append(f'<section id="{s.id}"><h2>{number}. {html.escape(s.title)}</h2>')
        parts += [f"<p>{html.escape(p)}</p>" for p in s.paragraphs]
        parts += [_html_table(t) for t in s.tables]
        for fid in s.figures:
            src = "data:image/png;base64," + base64.b64encode(pngs[fid]).decode("ascii")
            caption = html.escape(FIGURES[fid])
            parts.append(
                f'<figure id="{fid}"><img src="{src}" alt="{caption}">'
                f"<figcaption>{caption}</figcaption></figure>"
            )
        parts.append("</section>")
    payload = json.dumps(data, sort_keys=True).replace("</", "<\\/")
    parts.append(f'<script type="application/json" id="study-data">{payload}</script>')
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def _md_escape(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _markdown(title: str, meta: str, sections: list[Section], folder: str) -> str:
    lines = [f"# {title}", "", f"_{meta}_", ""]
    for number, s in enumerate(sections, start=1):
        lines += [f"## {number}. {s.title}", ""]
        for p in s.paragraphs:
            lines += [p, ""]
        for t in s.tables:
            lines += [f"**{_md_escape(t.caption)}**", ""]
            lines.append("| " + " | ".join(_md_escape(h) for h in t.header) + " |")
            lines.append("|" + "---|" * len(t.header))
            for row in t.rows:
                lines.append("| " + " | ".join(_md_escape(_text(i)) for i in row) + " |")
            lines.append("")
        for fid in s.figures:
            lines += [f"![{FIGURES[fid]}]({folder}/{fid}.png)", "", f"_{FIGURES[fid]}_", ""]
    return "\n".join(lines)


def _data(study: Any, sections: list[Section]) -> dict[str, Any]:
    tables = {
        t.id: {"header": t.header, "rows": [[_value(i) for i in row] for row in t.rows]}
        for s in sections
        for t in s.tables
    }
    checks = [
        {
            "clause": c.clause,
            "quantity": c.quantity,
            "value": c.value,
            "limit": c.limit,
            "kind": c.kind,
            "passes": c.passes,
        }
        for c in study.checks
    ]
    return {"tables": tables, "checks": checks, "figures": list(FIGURES)}


def write_report(study: Any, path: Path, *, command: str | None = None) -> tuple[Path, Path]:
    """Writes ``path`` (HTML) and ``path.with_suffix(".md")`` with the figures in
    ``<stem>_files/``; see :meth:`duhamel.design.Study.report`."""
    import duhamel

    if path.suffix.lower() not in (".html", ".htm"):
        raise ValueError(f"`path` must name an .html file, got {str(path)!r}")
    study.run()
    if command is None:
        command = " ".join(shlex.quote(a) for a in [Path(sys.executable).name, *sys.argv])
    sections = document(study, command)
    pngs = figures(study)
    n_runs = study.ensemble.stats.runs
    title = f"ASCE 7-22 isolated-building study: {study.building.name}"
    meta = (
        f"duhamel {duhamel.__version__}; {len(study.suite)} records x "
        f"{len(study.orientations)} orientations x {len(study.models)} property sets = "
        f"{n_runs} response-history runs; ASCE 7-22 chapters 16 and 17"
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(_html(title, meta, sections, pngs, _data(study, sections)), encoding="utf-8")
    folder = path.parent / f"{path.stem}_files"
    folder.mkdir(exist_ok=True)
    for fid, png in pngs.items():
        (folder / f"{fid}.png").write_bytes(png)
    md = path.with_suffix(".md")
    md.write_text(_markdown(title, meta, sections, folder.name), encoding="utf-8")
    return path, md
