"""``import duhamel`` stays light (no scipy.optimize, no matplotlib, lazy subpackages), and
the modules import one another without cycles.

Each check runs in a fresh interpreter (``sys.modules`` of the test session is already full).
The import time itself is not asserted (it depends on the machine); see ``python -X importtime
-c "import duhamel"``.
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import duhamel

#: The directory holding the package under test, put first on the child's path.
SOURCE = str(Path(duhamel.__file__).resolve().parents[1])
LAZY = ("analysis", "exact", "paper", "rotor")
#: Modules that may import scipy at module level when ``import duhamel`` runs: none. Every
#: module imports scipy inside the functions that need it.
SCIPY_ALLOWED: tuple[str, ...] = ()

#: Records which module first imported each heavy top-level package, then imports duhamel
#: and prints what it found as JSON.
PROBE = r"""
import json, sys

HEAVY = ("scipy", "matplotlib")
first = {}

class Probe:
    def find_spec(self, name, path=None, target=None):
        top = name.partition(".")[0]
        if top in HEAVY and top not in first:
            frame = sys._getframe(1)
            while frame is not None:
                module = frame.f_globals.get("__name__", "")
                if module.partition(".")[0] == "duhamel":
                    first[top] = module
                    break
                frame = frame.f_back
            else:
                first[top] = "?"
        return None

sys.meta_path.insert(0, Probe())
import duhamel

print(json.dumps({
    "modules": sorted(m for m in sys.modules if m.partition(".")[0] in HEAVY + ("duhamel",)),
    "first": first,
    "dir": dir(duhamel),
}))
"""


def run(code: str) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([SOURCE, env.get("PYTHONPATH", "")])
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )


@pytest.fixture(scope="module")
def probe() -> dict:
    done = run(PROBE)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.mark.parametrize(
    "heavy", ["scipy.optimize", "scipy.special", "scipy.signal", "scipy.integrate", "matplotlib"]
)
def test_import_duhamel_skips_heavy_modules(probe, heavy):
    assert heavy not in probe["modules"]


def test_lazy_subpackages_are_not_imported(probe):
    for name in LAZY:
        assert f"duhamel.{name}" not in probe["modules"]


def test_only_the_solve_path_imports_scipy(probe):
    importer = probe["first"].get("scipy")
    assert importer is None or importer.startswith(SCIPY_ALLOWED), (
        f"`import duhamel` imports scipy from {importer}: import it inside the functions that "
        "use it"
    )


def _module_level_imports(path: Path) -> set[str]:
    """Top-level packages imported by the module body (not inside functions or classes)."""
    out = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Import):
            out.update(alias.name.partition(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            out.add(node.module.partition(".")[0])
    return out


def test_modules_loaded_by_import_duhamel_import_scipy_only_inside_functions(probe):
    # The probe sees only the first importer of scipy; this checks every module it loaded.
    root = Path(duhamel.__file__).resolve().parents[1]
    loaded = [m for m in probe["modules"] if m.partition(".")[0] == "duhamel"]
    assert "duhamel.system" in loaded and "duhamel.elements" in loaded
    offenders = []
    for name in loaded:
        if name.startswith(SCIPY_ALLOWED):
            continue
        base = root.joinpath(*name.split("."))
        path = base / "__init__.py" if base.is_dir() else base.with_suffix(".py")
        if path.exists() and _module_level_imports(path) & {"scipy", "matplotlib"}:
            offenders.append(name)
    assert offenders == []


def test_dir_lists_the_lazy_subpackages(probe):
    for name in (*LAZY, "System", "solve", "loads"):
        assert name in probe["dir"]


def test_lazy_subpackages_resolve():
    code = (
        "import duhamel, sys\n"
        "assert 'duhamel.rotor' not in sys.modules\n"
        "from duhamel import rotor\n"
        "assert rotor is duhamel.rotor is sys.modules['duhamel.rotor']\n"
        "assert duhamel.rotor.Rotor.__name__ == 'Rotor'\n"
        "assert duhamel.analysis.amplification_matrix is not None\n"
        "assert callable(duhamel.exact.duffing)\n"
        "assert callable(duhamel.paper.rotor_orbits)\n"
        "import duhamel.paper.figures, duhamel.analysis.accuracy\n"
        "ns = {}\n"
        "exec('from duhamel import *', ns)\n"
        "assert all(name in ns for name in duhamel.__all__)\n"
        "try:\n"
        "    duhamel.no_such_thing\n"
        "except AttributeError as exc:\n"
        "    assert 'no_such_thing' in str(exc)\n"
        "else:\n"
        "    raise AssertionError('no AttributeError')\n"
    )
    done = run(code)
    assert done.returncode == 0, done.stderr


def test_lazy_subpackages_in_this_session():
    from duhamel import analysis, exact, paper, rotor

    assert duhamel.rotor is rotor and duhamel.paper is paper
    assert hasattr(analysis, "amplification_matrix") and hasattr(exact, "duffing")
    assert sorted(set(LAZY) - set(dir(duhamel))) == []


def _module_graph() -> dict[str, set[str]]:
    """Imports between duhamel's modules (a package ``__init__`` stands for what it imports),
    at any level: module level, inside functions and under ``TYPE_CHECKING``."""
    root = Path(duhamel.__file__).resolve().parent
    files = {}
    for path in root.rglob("*.py"):
        parts = path.relative_to(root.parent).with_suffix("").parts
        files[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    packages = {name for name, path in files.items() if path.name == "__init__.py"}
    imports: dict[str, set[str]] = {}
    for name, path in files.items():
        found = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parent = name.split(".")[: -node.level]
                    base = ".".join([*parent, base] if base else parent)
                for alias in node.names:
                    # `from package import module` needs the module; anything else, the
                    # package's __init__ (or the module named by `base`).
                    sub = f"{base}.{alias.name}"
                    found.add(sub if sub in files else base)
        imports[name] = {m for m in found if m in files and m != name}

    def resolve(modules: set[str], seen: frozenset[str] = frozenset()) -> set[str]:
        # A subpackage stands for the modules its __init__ imports (`from duhamel.elements
        # import Element` runs duhamel/elements/__init__.py); the root package does not.
        out = set()
        for m in modules:
            if m not in packages:
                out.add(m)
            elif m != root.name and m not in seen:
                out |= resolve(imports[m], seen | {m})
        return out

    return {
        name: resolve(found) - {name} for name, found in imports.items() if name not in packages
    }


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_import_cycles():
    graph = _module_graph()
    assert "duhamel.system" in graph and "duhamel.couplings" in graph["duhamel.system"]
    assert "duhamel.couplings" in graph["duhamel.analysis.chart"]  # through the package
    assert _cycles(graph) == [], "modules that import each other (use a Protocol)"


def test_cycle_detection_works():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_private_module_at_the_top_level():
    # Every concept lives in its package (elements/, results/, _engine/ ...); the top level
    # holds the public modules, the binding and its stub.
    root = Path(duhamel.__file__).resolve().parent
    private = sorted(
        p.name
        for p in root.iterdir()
        if p.name.startswith("_")
        and p.name not in ("__init__.py", "__main__.py", "__pycache__", "_core.pyi", "_engine")
        and not p.name.startswith("_core.")
    )
    assert private == []
