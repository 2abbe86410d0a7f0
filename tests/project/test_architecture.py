"""``docs/architecture.md`` (and ``docs/prepared.md``) name only files, directories and modules
that exist (issue 22); the Python blocks of ``docs/prepared.md`` run.

The rule (also at the end of the page):

* A backticked span is a *path* when it holds only letters, digits, ``_``, ``.``, ``-`` and
  ``/`` and either contains ``/`` or ends in ``.py``, ``.pyi``, ``.rs``, ``.md`` or ``.toml``;
  in a fenced block, each whitespace-separated word (end punctuation stripped) of those
  characters that ends in one of the suffixes or in ``/`` is a path.
* A path must exist relative to the repository root or to the page's directory (``docs/``);
  or, when the nearest heading above it names one of the trees ``crates/duhamel-core/src``,
  ``crates/duhamel-py/src``, ``python/duhamel`` (in backticks), relative to that tree; under
  any other heading, relative to any of the three. A trailing ``/`` asks for a directory.
* A backticked ``duhamel.a.b...`` resolves by files, without importing: each part a package
  (``__init__.py``) or a module (``.py`` or ``.pyi``) under ``python/``; after the first
  module, the next part a name its file defines at top level (function, class, assignment,
  import), and any further part a name defined in that class's body.
* A markdown link ``[text](target)`` that is not a URL or an anchor points to an existing
  file, relative to the page's directory.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "architecture.md"
PREPARED = ROOT / "docs" / "prepared.md"
TREES = ("crates/duhamel-core/src", "crates/duhamel-py/src", "python/duhamel")
SUFFIXES = (".py", ".pyi", ".rs", ".md", ".toml")

PATH_CHARS = re.compile(r"[A-Za-z0-9_.\-/]+")
MODULE = re.compile(r"duhamel(?:\.[A-Za-z_]\w*)+")
SPAN = re.compile(r"`([^`\n]+)`")
LINK = re.compile(r"\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#{1,6}\s")


@dataclass(frozen=True)
class Mention:
    """A name the page gives: a path, a Python module name or a link target."""

    kind: str  # "path", "module" or "link"
    text: str
    line: int
    tree: str | None  # the tree named by the nearest heading above, if any


def is_path(token: str) -> bool:
    return (
        PATH_CHARS.fullmatch(token) is not None
        and token.strip("./") != ""
        and ("/" in token or token.endswith(SUFFIXES))
    )


def mentions(text: str) -> list[Mention]:
    """Every path, module name and link of a markdown page, with its line and tree."""
    found: list[Mention] = []
    fenced = False
    tree: str | None = None
    for number, line in enumerate(text.splitlines(), start=1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            for word in line.split():
                word = word.strip(",;:()[]'\"")
                if (word.endswith(SUFFIXES) or word.endswith("/")) and is_path(word):
                    found.append(Mention("path", word, number, tree))
            continue
        if HEADING.match(line):
            named = [t for t in SPAN.findall(line) if t.rstrip("/") in TREES]
            tree = named[0].rstrip("/") if named else None
        for span in SPAN.findall(line):
            span = span.strip()
            if is_path(span):
                found.append(Mention("path", span, number, tree))
            elif MODULE.fullmatch(span):
                found.append(Mention("module", span, number, tree))
        for target in LINK.findall(SPAN.sub("", line)):
            if not re.match(r"[a-z]+:|#", target):
                found.append(Mention("link", target.split("#")[0], number, tree))
    return found


def path_exists(token: str, tree: str | None, root: Path, page_dir: Path) -> bool:
    rel = token.rstrip("/")
    bases = [root, page_dir, *([root / tree] if tree else [root / t for t in TREES])]
    if token.endswith("/"):
        return any((base / rel).is_dir() for base in bases)
    return any((base / rel).exists() for base in bases)


def _defined(body: list[ast.stmt]) -> dict[str, ast.stmt]:
    """Names a module or class body defines, with their statements."""
    names: dict[str, ast.stmt] = {}
    for node in body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names[node.name] = node
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    names[target.id] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = node
        elif isinstance(node, ast.Import | ast.ImportFrom):
            for alias in node.names:
                names[(alias.asname or alias.name).split(".")[0]] = node
        elif isinstance(node, ast.If):  # `if TYPE_CHECKING:` imports
            names.update(_defined(node.body))
    return names


def module_exists(name: str, root: Path) -> bool:
    """Whether `name` (``duhamel.a.b...``) resolves by files under ``root / "python"``."""
    parts = name.split(".")
    here = root / "python"
    file: Path | None = None
    while parts:
        part = parts[0]
        package = here / part
        if (package / "__init__.py").is_file():
            here, file, parts = package, package / "__init__.py", parts[1:]
            continue
        modules = [here / f"{part}.py", here / f"{part}.pyi"]
        module = next((m for m in modules if m.is_file()), None)
        if module is not None:
            file, parts = module, parts[1:]
        break
    if not parts:
        return True
    if file is None:
        return False
    body = ast.parse(file.read_text()).body
    for i, part in enumerate(parts):
        node = _defined(body).get(part)
        if node is None:
            return False
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("duhamel."):
            # A name re-exported from another duhamel module: resolve it there.
            alias = next(a for a in node.names if (a.asname or a.name) == part)
            return module_exists(".".join([node.module, alias.name, *parts[i + 1 :]]), root)
        body = node.body if isinstance(node, ast.ClassDef) else []
    return True


def missing(text: str, root: Path = ROOT, page_dir: Path | None = None) -> list[str]:
    """What a page names that does not exist, as ``line N: kind `text```."""
    page_dir = root / "docs" if page_dir is None else page_dir
    bad = []
    for m in mentions(text):
        if m.kind == "path":
            ok = path_exists(m.text, m.tree, root, page_dir)
        elif m.kind == "module":
            ok = module_exists(m.text, root)
        else:
            ok = (page_dir / m.text).exists()
        if not ok:
            where = f" (under the heading naming {m.tree})" if m.tree else ""
            bad.append(f"line {m.line}: {m.kind} `{m.text}`{where}")
    return bad


@pytest.mark.parametrize("page", [DOC, PREPARED], ids=lambda p: p.name)
def test_the_page_names_only_what_exists(page):
    bad = missing(page.read_text())
    assert not bad, (
        f"docs/{page.name} names paths, modules or links that do not exist (rename them "
        "in the page, or the rule in tests/project/test_architecture.py):\n" + "\n".join(bad)
    )


def test_the_prepared_runs_page_runs():
    """docs/prepared.md's Python blocks run as written, one after the other (its asserts:
    a prepared run equals solve, and solve_many's reuse equals the loop, bit for bit)."""
    blocks = re.findall(r"```python\n(.*?)```", PREPARED.read_text(), re.S)
    assert len(blocks) >= 2
    namespace: dict = {}
    for code in blocks:
        exec(compile(code, str(PREPARED), "exec"), namespace)
    assert namespace["prepared"].route == "pseudo-force"
    assert len(namespace["ens"].results) == len(namespace["params"])


def test_the_page_is_read():
    """The parser sees the page's names (a regex that stopped matching would pass silently)."""
    found = mentions(DOC.read_text())
    kinds = {m.kind for m in found}
    assert kinds == {"path", "module", "link"}
    assert len([m for m in found if m.kind == "path"]) >= 80
    texts = {m.text for m in found}
    for name in ("_engine/dispatch.py", "model.rs", "driver.rs", "prepared.py", "store/"):
        assert name in texts
    trees = {m.tree for m in found}
    assert set(TREES) <= trees


CHECKED = """\
# A page

```text
prepare -> Prepared                    prepared.py
ghost/                                 _engine/phantom.py   schemes a/b/c;
```

Real: `prepared.py`, `_engine/dispatch.py`, `store/`, `tests/project/test_stub.py`, `Cargo.toml`,
`duhamel.prepare`, `duhamel.Prepared.run`, `duhamel._core.ModalModel`,
`duhamel._engine.dispatch`, [store](store.md). Not paths: `"first-order"`, `t0 + n dt`,
`a | b`, `x`, [site](https://example.org), [here](#a-page).

Fake: `python/duhamel/nowhere.py`, `no_such.rs`, `prepared.py/`, `duhamel._engine.nowhere`,
`duhamel.prepared.no_such_name`, `duhamel.Prepared.no_such_method`, [gone](gone.md).

### Binding (`crates/duhamel-py/src`)

`model.rs` is the binding's; `kernel/oscillator.rs` is the core's, not the binding's.
"""


def test_the_checker_catches_what_does_not_exist():
    bad = missing(CHECKED)
    named = {line.split("`")[1] for line in bad}
    assert named == {
        "ghost/",
        "_engine/phantom.py",
        "python/duhamel/nowhere.py",
        "no_such.rs",
        "prepared.py/",
        "duhamel._engine.nowhere",
        "duhamel.prepared.no_such_name",
        "duhamel.Prepared.no_such_method",
        "gone.md",
        "kernel/oscillator.rs",
    }
    assert any("crates/duhamel-py/src" in line for line in bad if "kernel/oscillator.rs" in line)
    assert "line 5: path `ghost/`" in bad
