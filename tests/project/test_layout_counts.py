"""Issue 35's layout acceptance, counted from the source (``benchmarks/counts.py`` computes
the counts and prints them with the raw word-grep ones beside them).

In the library (``python/duhamel`` without the OpenSees importer, ``crates/*/src`` without
test code): each built-in element named in code in at most 5 files, no ``_spec`` name, no
switch on type names, ``LinearCoupling`` special-cased in at most 2 files; and the Python
library names a built-in element, outside the stub and the package's export list, only to
import, build or annotate one (never to test an object's type)."""

from __future__ import annotations

import ast
import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec_file = importlib.util.spec_from_file_location("_counts", ROOT / "benchmarks" / "counts.py")
assert _spec_file is not None and _spec_file.loader is not None
counts = importlib.util.module_from_spec(_spec_file)
sys.modules["_counts"] = counts
_spec_file.loader.exec_module(counts)

REGISTRATION = ("python/duhamel/_core.pyi", "python/duhamel/elements/__init__.py")


@pytest.fixture(scope="module")
def measured():
    return counts.measure()


def test_the_measure_sees_code_and_not_text():
    """The code measure counts names used by code, not those in strings, comments, docstrings,
    Rust doc comments or test modules; the switch finder sees a name bound to a type's name."""
    python = '"""Bilinear"""\n# Gap\nx = "Spring"\ny = Cubic(0)\n'
    assert counts.python_code_names(python) >= {"x", "y", "Cubic"}
    assert not counts.python_code_names(python) & {"Bilinear", "Gap", "Spring"}
    rust = (
        '/// Bilinear\n// Gap\nconst N: &str = "Spring"; let c = Cubic::new();\n'
        "#[cfg(test)]\nmod tests { use super::Polynomial; }\nfn f<'a>(x: &'a Damper) {}\n"
    )
    names = counts.rust_code_names(rust)
    assert {"Cubic", "Damper", "N"} <= names
    assert not names & {"Bilinear", "Gap", "Spring", "Polynomial"}
    switch = "def f(e):\n    name = type(e).__name__\n    if name in ('A', 'B'):\n        pass\n"
    assert counts.python_type_switches(switch) == [(3, ["A", "B"])]
    message = "def f(e):\n    raise TypeError(f'got {type(e).__name__}')\n"
    assert counts.python_type_switches(message) == []
    arm = 'match name {\n    "Gap" => 1,\n    _ => 0,\n}\n'
    assert counts.rust_type_switches(arm, ["Gap"]) == [(2, "Gap")]
    modules = {
        "pkg.blocks": "class Series:\n    pass\n",
        "pkg.user": "from pkg.blocks import Series\nc = Series()\n",
        "pkg.again": "from pkg.user import Series\n",
        "pkg.both": "from pkg.blocks import Series\nimport duhamel\ne = duhamel.elements.Series\n",
        "pkg.element": "from duhamel.elements import Series\n",
    }
    homonyms = counts.python_homonyms(modules, {"Series", "Gap"})
    assert homonyms == {m: {"Series"} for m in ("pkg.blocks", "pkg.user", "pkg.again")}
    coupled = "if isinstance(e, Element | LinearCoupling): pass\n"
    assert counts.coupling_special_cases(coupled) == [1]


def test_element_names_are_the_registry(measured):
    """The elements counted are the Rust registry's, each a class of duhamel.elements."""
    import duhamel.elements

    assert len(measured.elements) >= 15
    for name in measured.elements:
        assert issubclass(getattr(duhamel.elements, name), duhamel.elements.Element)


def test_each_element_named_in_at_most_five_files(measured):
    over = {n: f for n, f in measured.elements.items() if len(f) > 5}
    assert not over, "\n".join(f"{n} ({len(f)}): {f}" for n, f in over.items())


def _misuses(text: str, classes: set[str]) -> list[tuple[int, str]]:
    """Code uses of the names `classes` other than an import, a call or an annotation (a
    class the module defines itself under such a name, as the rotor's controller `Series`,
    is its own, not the element)."""
    tree = ast.parse(text)
    classes = classes - {n.name for n in ast.walk(tree) if isinstance(n, ast.ClassDef)}
    allowed: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            allowed.add(id(node.func))
        annotations = []
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            annotations.append(node.returns)
            a = node.args
            annotations += [x.annotation for x in [*a.posonlyargs, *a.args, *a.kwonlyargs]]
            annotations += [x.annotation for x in (a.vararg, a.kwarg) if x is not None]
        elif isinstance(node, ast.AnnAssign):
            annotations.append(node.annotation)
        for ann in annotations:
            if ann is not None:
                allowed.update(id(n) for n in ast.walk(ann))
    out = []
    for node in ast.walk(tree):
        name = (
            node.id
            if isinstance(node, ast.Name)
            else node.attr
            if isinstance(node, ast.Attribute)
            else None
        )
        if name in classes and id(node) not in allowed:
            out.append((node.lineno, name))
    return out


def test_python_library_only_builds_elements(measured):
    """Outside the stub and the export list, the Python library names a built-in element
    only to import, build or annotate one: no isinstance on element types."""
    classes = set(measured.elements)
    found = {}
    for path in counts.library_files():
        where = path.relative_to(ROOT).as_posix()
        if path.suffix == ".py" and where not in REGISTRATION:
            bad = _misuses(path.read_text(encoding="utf-8"), classes)
            if bad:
                found[where] = bad
    assert not found, found


def test_no_spec_protocol(measured):
    assert measured.spec == []


def test_no_switch_on_type_names(measured):
    assert measured.switches == {}


def test_linear_coupling_special_cased_in_at_most_two_files(measured):
    assert len(measured.coupling) <= 2, measured.coupling
