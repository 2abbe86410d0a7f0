"""BENCHMARKS.md stays a page of current numbers that a reader can follow (issue 35): every
command it lists names a script of ``benchmarks/`` and only options that script defines,
every link into it (from the README, ``benchmarks/README.md`` and ``docs/``, and its own
index) names a heading it has, and it stays short."""

from __future__ import annotations

import re
import shlex
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "BENCHMARKS.md"
SPAN = re.compile(r"`([^`\n]+)`")
SCRIPT = re.compile(r"benchmarks/(\w+)\.py")
LINK = re.compile(r"\]\(([^)\s]*?)#([^)\s]+)\)")
MAX_LINES = 320  # the issue: "at most about 300 lines"; history lives in git


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces as hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(text: str) -> set[str]:
    """Every anchor of a markdown page (repeated headings get -1, -2, ... as on GitHub)."""
    seen: Counter[str] = Counter()
    found: set[str] = set()
    fenced = False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if fenced or not re.match(r"#{1,6} ", line):
            continue
        base = slug(line.lstrip("#"))
        found.add(f"{base}-{seen[base]}" if seen[base] else base)
        seen[base] += 1
    return found


def commands(text: str) -> list[tuple[str, list[str]]]:
    """Each code span that runs a script of benchmarks/: the script and the options after it."""
    found = []
    for span in SPAN.findall(text):
        match = SCRIPT.search(span)
        if match is None:
            continue
        words = shlex.split(span[match.end() :])
        options = [w.strip("[]") for w in words if w.strip("[]").startswith("--")]
        found.append((match.group(1), options))
    return found


def test_slug_follows_github() -> None:
    assert slug("Beyond the core's loop") == "beyond-the-cores-loop"
    assert slug("Corrected reduced models: the substep rule") == (
        "corrected-reduced-models-the-substep-rule"
    )
    assert anchors("# A\n## A\n```\n# not a heading\n```\n") == {"a", "a-1"}


def test_commands_name_existing_scripts_and_options() -> None:
    found = commands(PAGE.read_text(encoding="utf-8"))
    assert len(found) >= 25, "the page lists the command of every comparison"
    bad = []
    for script, options in found:
        path = ROOT / "benchmarks" / f"{script}.py"
        if not path.is_file():
            bad.append(f"benchmarks/{script}.py does not exist")
            continue
        source = path.read_text(encoding="utf-8")
        shared = "_section" in source  # its command line: --append and --quick
        for option in options:
            if f'"{option}"' not in source and not (shared and option in ("--append", "--quick")):
                bad.append(f"benchmarks/{script}.py has no option {option}")
    assert not bad, bad


def test_every_script_is_on_the_page() -> None:
    text = PAGE.read_text(encoding="utf-8")
    listed = {script for script, _ in commands(text)}
    scripts = {p.stem for p in (ROOT / "benchmarks").glob("*.py") if not p.stem.startswith("_")}
    # nonlinear.py is run by run.py (its second section) and has no command of its own
    assert scripts - listed - {"nonlinear"} == set()


def test_table1_command_names_what_exists() -> None:
    from duhamel.paper.rotor import Table1Data, table1

    assert callable(table1)
    assert hasattr(Table1Data, "newmark_ratio") and hasattr(Table1Data, "relative_cpu")


def test_links_into_the_page_name_its_headings() -> None:
    targets = anchors(PAGE.read_text(encoding="utf-8"))
    pages = [ROOT / "README.md", ROOT / "benchmarks" / "README.md", PAGE]
    pages += sorted((ROOT / "docs").rglob("*.md"))
    bad = []
    for page in pages:
        for file, anchor in LINK.findall(page.read_text(encoding="utf-8")):
            into = file.endswith("BENCHMARKS.md") or (page == PAGE and file == "")
            if into and anchor not in targets:
                bad.append(f"{page.relative_to(ROOT)}: #{anchor}")
    assert not bad, bad


def test_page_stays_short() -> None:
    lines = PAGE.read_text(encoding="utf-8").count("\n")
    assert lines <= MAX_LINES, f"BENCHMARKS.md has {lines} lines; condense (history is in git)"
