"""The layout counts of issue 35's acceptance, computed from the source.

In the library (``python/duhamel`` and ``crates/*/src``; the OpenSees importer
``python/duhamel/opensees`` and Rust test files excepted), two measures of each count:

* **code**: names as the code uses them — Python tokens outside strings, comments and
  docstrings (``tokenize``), Rust identifiers outside comments, doc comments and string or
  character literals;
* **raw**: a whole-word grep of the files (comments, docstrings and messages included).

A Python name that is not the element is not counted in the code measure: a class a module
defines under an element's name (the rotor's controller ``Series``) and that name where
other modules import it from there (``python_homonyms``; they are printed). Rust homonyms
are not recognised: they are given names of their own.

Counted: the files naming each built-in element class (``duhamel._core.element_names()``,
the Rust registry's list); ``_spec`` names; switches on type names (a ``__name__`` compared
with, or tested for membership in, string literals, directly or through a variable bound to
it; in Rust a match arm or comparison on an element's name as a string literal); the files
that special-case ``LinearCoupling`` (``isinstance``/``issubclass`` with it, ``type(x) is``
it, or its name compared); the files mentioning energy. ``tests/project/test_layout_counts.py``
checks the code measures against the acceptance.

Run: ``PYTHONPATH=python python benchmarks/counts.py`` (``-v``: the files naming each element)
"""

from __future__ import annotations

import ast
import io
import re
import sys
import tokenize
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COUPLING = "LinearCoupling"
_NAME_ATTRS = ("__name__", "__qualname__")


def library_files() -> list[Path]:
    """The library's Python and Rust files (the OpenSees importer and Rust tests excepted)."""
    package = ROOT / "python" / "duhamel"
    python = [
        p
        for p in sorted(package.rglob("*.py*"))
        if p.suffix in (".py", ".pyi") and (package / "opensees") not in p.parents
    ]
    rust = [
        p
        for p in sorted(ROOT.glob("crates/*/src/**/*.rs"))
        if not p.name.endswith("_tests.rs") and p.name != "tests.rs" and "tests" not in p.parts
    ]
    return python + rust


def element_names() -> list[str]:
    """The built-in element classes: the Rust registry's list, as the binding exports it."""
    from duhamel import _core

    return [name for name, *_ in _core.element_names()]


def _python_tokens(text: str) -> Iterator[tokenize.TokenInfo]:
    return tokenize.generate_tokens(io.StringIO(text).readline)


def python_code_names(text: str) -> set[str]:
    """The names a Python file uses in code (not in strings, comments or docstrings)."""
    return {t.string for t in _python_tokens(text) if t.type == tokenize.NAME}


_RUST_LEXEME = re.compile(
    r"""
      (?P<line>//[^\n]*)
    | (?P<block>/\*.*?\*/)
    | (?P<raw>b?r(?P<hashes>\#*)".*?"(?P=hashes))
    | (?P<string>b?"(?:\\.|[^"\\])*")
    | (?P<char>b?'(?:\\.|[^'\\])')
    """,
    re.VERBOSE | re.DOTALL,
)


def rust_code(text: str, keep_strings: bool = False) -> str:
    """A Rust file with its comments (doc comments included) and, unless `keep_strings`, its
    string and character literals blanked (lifetimes stay)."""

    def blank(m: re.Match[str]) -> str:
        if keep_strings and (m.group("string") or m.group("raw") or m.group("char")):
            return m.group(0)
        return " "

    return _RUST_LEXEME.sub(blank, text)


def without_tests(code: str) -> str:
    """Rust code (comments and strings blanked) without its ``#[cfg(test)]`` items."""
    out, start = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]", code):
        if m.start() < start:
            continue
        brace = code.find("{", m.end())
        semi = code.find(";", m.end())
        if brace < 0 or 0 <= semi < brace:  # a `use` or a declaration: to its `;`
            end = semi + 1
        else:
            depth, end = 0, brace
            for end in range(brace, len(code)):
                depth += {"{": 1, "}": -1}.get(code[end], 0)
                if depth == 0:
                    break
            end += 1
        out.append(code[start : m.start()])
        start = end
    out.append(code[start:])
    return "".join(out)


def rust_code_names(text: str) -> set[str]:
    """The identifiers a Rust file uses in code (test modules excepted)."""
    return set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", without_tests(rust_code(text))))


def code_names(path: Path) -> set[str]:
    text = path.read_text(encoding="utf-8")
    return rust_code_names(text) if path.suffix == ".rs" else python_code_names(text)


def module_name(path: Path) -> str:
    """The dotted module name of a library Python file (``duhamel.rotor.controllers``)."""
    parts = list(path.relative_to(ROOT / "python").with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


#: The modules through which a Python file takes a built-in element itself.
ELEMENT_MODULES = ("duhamel", "duhamel.elements", "duhamel._core")


def python_homonyms(texts: dict[str, str], classes: set[str]) -> dict[str, set[str]]:
    """Per module (``{module: source}``), the element names it binds to something else: a
    class it defines under that name (the rotor's controller ``Series``), or a name it
    imports from a module that binds it so, until no more are found. Such a name in that
    file is the homonym, not the element, unless the file also takes the element itself (an
    import from ``duhamel``, ``duhamel.elements`` or ``duhamel._core``, or an attribute
    ``x.Name``)."""
    trees = {m: ast.parse(t) for m, t in texts.items()}
    bound: dict[str, set[str]] = {
        m: {n.name for n in tree.body if isinstance(n, ast.ClassDef)} & classes
        for m, tree in trees.items()
    }
    changed = True
    while changed:
        changed = False
        for m, tree in trees.items():
            for n in ast.walk(tree):
                if isinstance(n, ast.ImportFrom) and n.module in bound and n.level == 0:
                    found = {a.name for a in n.names} & bound[n.module] - bound[m]
                    if found:
                        bound[m] |= found
                        changed = True
    out: dict[str, set[str]] = {}
    for m, names in bound.items():
        element = set()
        for n in ast.walk(trees[m]):
            if isinstance(n, ast.ImportFrom) and n.module in ELEMENT_MODULES:
                element |= {a.name for a in n.names}
            elif isinstance(n, ast.Attribute):
                element.add(n.attr)
        if names - element:
            out[m] = names - element
    return out


def rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def files_naming(name: str, files: list[Path], names: dict[Path, set[str]]) -> list[str]:
    """The files whose code names `name`."""
    return [rel(p) for p in files if name in names[p]]


def raw_files_naming(word: str, files: list[Path]) -> list[str]:
    """The files in which `word` occurs as a whole word anywhere (grep -lw)."""
    pattern = re.compile(rf"\b{re.escape(word)}\b")
    return [rel(p) for p in files if pattern.search(p.read_text(encoding="utf-8"))]


# ------------------------------------------------------------------ switches on type names
def _is_type_name(node: ast.AST, bound: set[str]) -> bool:
    """``x.__name__`` (``type(x).__name__``, ``cls.__qualname__``) or a name bound to one."""
    if isinstance(node, ast.Attribute) and node.attr in _NAME_ATTRS:
        return True
    return isinstance(node, ast.Name) and node.id in bound


def _literal_strings(node: ast.AST) -> list[str] | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.Tuple | ast.List | ast.Set) and node.elts:
        out = [e.value for e in node.elts if isinstance(e, ast.Constant)]
        if len(out) == len(node.elts) and all(isinstance(s, str) for s in out):
            return out
    return None


def _scopes(tree: ast.AST) -> Iterator[ast.AST]:
    yield tree
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            yield node


def _own_nodes(scope: ast.AST) -> Iterator[ast.AST]:
    """The nodes of `scope` outside its nested functions."""
    stack = list(ast.iter_child_nodes(scope))
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            stack.extend(ast.iter_child_nodes(node))


def python_type_switches(text: str) -> list[tuple[int, list[str]]]:
    """``(line, names)`` of each comparison of a type's name with string literals (``==``,
    ``!=``, ``in``, ``not in``, a ``match`` case), directly or through a local name bound to
    ``x.__name__``. Messages that only print the name are not switches."""
    out: list[tuple[int, list[str]]] = []
    for scope in _scopes(ast.parse(text)):
        nodes = list(_own_nodes(scope))
        bound = {
            t.id
            for n in nodes
            if isinstance(n, ast.Assign) and _is_type_name(n.value, set())
            for t in n.targets
            if isinstance(t, ast.Name)
        }
        for n in nodes:
            if isinstance(n, ast.Compare):
                operands = [n.left, *n.comparators]
                if any(_is_type_name(o, bound) for o in operands):
                    for o in operands:
                        strings = _literal_strings(o)
                        if strings is not None:
                            out.append((n.lineno, strings))
            elif isinstance(n, ast.Match) and _is_type_name(n.subject, bound):
                strings = [
                    p.value.value
                    for c in n.cases
                    for p in ast.walk(c.pattern)
                    if isinstance(p, ast.MatchValue) and isinstance(p.value, ast.Constant)
                ]
                out.append((n.lineno, [str(s) for s in strings]))
    return out


def rust_type_switches(text: str, class_names: list[str]) -> list[tuple[int, str]]:
    """``(line, name)`` of each match arm (``"Name" =>``) or comparison (``== "Name"``) on a
    class name as a string literal."""
    code = rust_code(text, keep_strings=True)
    names = "|".join(map(re.escape, class_names))
    pattern = re.compile(
        rf'"({names})"\s*(?:=>|\||if\b)|(?:==|!=)\s*"({names})"|"({names})"\s*(?:==|!=)'
    )
    return [
        (code.count("\n", 0, m.start()) + 1, next(g for g in m.groups() if g))
        for m in pattern.finditer(code)
    ]


# ------------------------------------------------------------------ couplings special-cased
def _names_coupling(node: ast.AST) -> bool:
    return any(
        (isinstance(n, ast.Name) and n.id == COUPLING)
        or (isinstance(n, ast.Attribute) and n.attr == COUPLING)
        for n in ast.walk(node)
    )


def coupling_special_cases(text: str) -> list[int]:
    """Lines that special-case ``LinearCoupling``: ``isinstance``/``issubclass`` with it,
    ``type(x) is`` it, or its name compared."""
    lines = []
    for n in ast.walk(ast.parse(text)):
        if (
            isinstance(n, ast.Call)
            and isinstance(n.func, ast.Name)
            and n.func.id in ("isinstance", "issubclass")
            and len(n.args) == 2
            and _names_coupling(n.args[1])
        ):
            lines.append(n.lineno)
        elif isinstance(n, ast.Compare) and any(
            isinstance(op, ast.Is | ast.IsNot | ast.Eq | ast.NotEq) for op in n.ops
        ):
            operands = [n.left, *n.comparators]
            if any(_names_coupling(o) for o in operands) and any(
                isinstance(o, ast.Call) and getattr(o.func, "id", None) == "type" for o in operands
            ):
                lines.append(n.lineno)
    lines += [line for line, names in python_type_switches(text) if COUPLING in names]
    return sorted(set(lines))


# ------------------------------------------------------------------ the report
@dataclass
class Counts:
    """Every count, both measures (file lists, or ``path:line`` sites)."""

    n_files: int
    homonyms: dict[str, set[str]]
    elements: dict[str, list[str]]
    elements_raw: dict[str, list[str]]
    spec: list[str]
    spec_raw: list[str]
    switches: dict[str, list[tuple[int, list[str]]]]
    switches_raw: list[str]
    coupling: dict[str, list[int]]
    coupling_raw: list[str]
    coupling_files_raw: list[str]
    energy_raw: list[str]


def _lines_matching(pattern: str, files: list[Path], texts: dict[Path, str]) -> list[str]:
    found = re.compile(pattern)
    return [
        f"{rel(p)}:{i + 1}"
        for p in files
        for i, line in enumerate(texts[p].splitlines())
        if found.search(line)
    ]


def measure() -> Counts:
    """Every count, both measures."""
    files = library_files()
    texts = {p: p.read_text(encoding="utf-8") for p in files}
    names = {p: code_names(p) for p in files}
    python = [p for p in files if p.suffix != ".rs"]
    classes = element_names()
    modules = {module_name(p): p for p in python if p.suffix == ".py"}
    homonyms = python_homonyms({m: texts[p] for m, p in modules.items()}, set(classes))
    for m, found in homonyms.items():
        names[modules[m]] -= found
    switches: dict[str, list[tuple[int, list[str]]]] = {}
    coupling: dict[str, list[int]] = {}
    for p in python:
        if found := python_type_switches(texts[p]):
            switches[rel(p)] = found
        if lines := coupling_special_cases(texts[p]):
            coupling[rel(p)] = lines
    for p in files:
        if p.suffix == ".rs" and (arms := rust_type_switches(texts[p], [*classes, COUPLING])):
            switches[rel(p)] = [(line, [name]) for line, name in arms]
    return Counts(
        n_files=len(files),
        homonyms={rel(modules[m]): found for m, found in homonyms.items()},
        elements={n: files_naming(n, files, names) for n in classes},
        elements_raw={n: raw_files_naming(n, files) for n in classes},
        spec=files_naming("_spec", files, names),
        spec_raw=raw_files_naming("_spec", files),
        switches=switches,
        switches_raw=_lines_matching(
            r"__name__\s*(?:==|!=|\bin\b|\bnot in\b)|(?:==|!=)\s*\w+\.__name__", python, texts
        ),
        coupling=coupling,
        coupling_raw=_lines_matching(rf"isinstance\(.*\b{COUPLING}\b", python, texts),
        coupling_files_raw=raw_files_naming(COUPLING, files),
        energy_raw=[rel(p) for p in files if re.search("energy", texts[p], re.IGNORECASE)],
    )


def main() -> None:
    m = measure()
    print(f"library files counted: {m.n_files} (python/duhamel without opensees/, crates/*/src)")
    print(f"{'element':<24}{'code':>6}{'raw':>6}   files naming it (code: Python tokens, Rust")
    print(f"{'':<36}   identifiers outside comments, strings, test modules; raw: grep -lw)")
    for name, found in m.elements.items():
        print(f"{name:<24}{len(found):>6}{len(m.elements_raw[name]):>6}")
    print(f"not counted, homonyms (the file's own class or one imported from it): {m.homonyms}")
    print(f"_spec: code {len(m.spec)} files, raw {len(m.spec_raw)} files")
    print(f"switches on type names (code): {sum(map(len, m.switches.values()))} {m.switches}")
    print(f"  raw, lines comparing a __name__: {len(m.switches_raw)} {m.switches_raw}")
    print(f"LinearCoupling special-cased (code): {len(m.coupling)} files {m.coupling}")
    print(
        f"  raw: {len(m.coupling_raw)} lines with isinstance(..LinearCoupling..), "
        f"{len(m.coupling_files_raw)} files naming it"
    )
    print(f"files mentioning energy (raw, any case): {len(m.energy_raw)}")
    if "-v" in sys.argv:
        for name, found in m.elements.items():
            print(f"{name}: {found}")


if __name__ == "__main__":
    main()
