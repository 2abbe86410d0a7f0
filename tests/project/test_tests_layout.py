"""tests/ is laid out like the package (issue 35, item 6; the map is in tests/__init__.py).

Every test file sits in a folder of tests/, never at its top level; each package of
python/duhamel has its folder (``engine`` for ``_engine``) and every other folder is one of
the few named here for what it mirrors; every folder is a Python package, so that pytest
imports ``tests/rotor/test_rotor.py`` as ``tests.rotor.test_rotor`` and two folders may hold
files of the same name; the shared helpers live in ``tests/_support`` (on pytest's
``pythonpath``), which holds no tests. A test file named anywhere (docs, README, benchmarks,
the library's comments, the tests themselves) is named by its path in the folders.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TESTS = ROOT / "tests"
PACKAGE = ROOT / "python" / "duhamel"
SUPPORT = "_support"

#: The folders that do not mirror a package of python/duhamel, and what they hold.
OTHER = {
    "system": "the top-level modules of python/duhamel (system.py, modal.py, runs.py, ...)",
    "examples": "the scripts of examples/",
    "robustness": "the robustness contract over the whole public API",
    "project": "repo-wide checks (docs, stub, types, layout, README)",
}


def folders() -> list[Path]:
    return sorted(p for p in TESTS.iterdir() if p.is_dir() and p.name != "__pycache__")


def packages() -> set[str]:
    """The packages of python/duhamel, named as their test folders (``_engine`` -> ``engine``)."""
    return {p.name.lstrip("_") for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}


def test_no_test_file_at_the_top_of_tests():
    loose = sorted(p.name for p in TESTS.glob("*.py") if p.name != "__init__.py")
    assert not loose, f"test files and helpers belong in a folder of tests/: {loose}"


def test_every_package_has_its_folder_and_every_folder_mirrors_something():
    names = {p.name for p in folders()} - {SUPPORT}
    assert "engine" in packages() and "rotor" in packages()  # the walk found the packages
    missing = packages() - names
    assert not missing, f"packages of python/duhamel without a folder in tests/: {missing}"
    unknown = names - packages() - set(OTHER)
    assert not unknown, f"folders of tests/ that mirror no package (add to OTHER?): {unknown}"
    assert (ROOT / "examples").is_dir()


def test_every_test_folder_is_a_package_of_tests():
    assert (TESTS / "__init__.py").is_file()
    for folder in folders():
        if folder.name == SUPPORT:
            continue
        assert (folder / "__init__.py").is_file(), f"{folder} has no __init__.py"
        tests = list(folder.glob("test_*.py"))
        assert tests, f"{folder} holds no tests"
        deeper = [p for p in folder.rglob("test_*.py") if p.parent != folder]
        assert not deeper, f"test files below the folders' level: {deeper}"


def test_the_helpers_are_on_pytests_path_and_hold_no_tests():
    support = TESTS / SUPPORT
    helpers = sorted(p.name for p in support.glob("*.py"))
    assert helpers and all(name.startswith("_") for name in helpers), helpers
    assert not (support / "__init__.py").exists(), "the helpers import as `_models`, not a package"
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert f"tests/{SUPPORT}" in config["tool"]["pytest"]["ini_options"]["pythonpath"]


def test_every_test_path_named_in_the_repository_exists():
    """``tests/.../test_x.py`` in a page, a benchmark or a comment names a file that exists."""
    texts = [ROOT / name for name in ("README.md", "BENCHMARKS.md", "pyproject.toml", "Makefile")]
    texts += [ROOT / ".ci" / "run"]
    for tree, suffixes in (
        ("docs", {".md"}),
        ("benchmarks", {".py"}),
        ("examples", {".py"}),
        ("python", {".py", ".pyi"}),
        ("tests", {".py"}),
        ("crates", {".rs"}),
    ):
        texts += [p for p in (ROOT / tree).rglob("*") if p.suffix in suffixes]
    path = re.compile(r"(?<![\w/.-])tests/[\w/]*\w\.py")
    named = {
        (text.relative_to(ROOT).as_posix(), found)
        for text in texts
        if text.is_file()
        for found in path.findall(text.read_text(encoding="utf-8"))
    }
    assert ("docs/architecture.md", "tests/project/test_stub.py") in named  # the scan reads
    missing = sorted(f"{where}: {found}" for where, found in named if not (ROOT / found).is_file())
    assert not missing, "test files named by their old path:\n" + "\n".join(missing)
