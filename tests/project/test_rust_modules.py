"""The Rust crates' modules import one another without cycles, and stay small.

A module's dependencies are the modules its ``use`` declarations name (``crate::``,
``super::``, ``self::`` and its own children), tests excluded; a cycle is a path of such
dependencies that comes back to where it started (a parent that re-exports a child that uses
the parent counts).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

CRATES = Path(__file__).resolve().parents[2] / "crates"
SOURCES = [CRATES / "duhamel-core" / "src", CRATES / "duhamel-py" / "src"]

USE = re.compile(r"^\s*(?:pub(?:\([^)]*\))? )?use ([\w:]+)", re.M)
MOD = re.compile(r"^\s*(?:pub(?:\([^)]*\))? )?mod (\w+);", re.M)


def module_path(src: Path, file: Path) -> tuple[str, ...]:
    parts = list(file.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts.pop()
    return ("crate", *parts)


def dependencies(src: Path) -> dict[tuple[str, ...], set[tuple[str, ...]]]:
    files = {module_path(src, f): f for f in src.rglob("*.rs")}
    graph: dict[tuple[str, ...], set[tuple[str, ...]]] = {}
    for module, file in files.items():
        text = file.read_text().split("#[cfg(test)]")[0]
        children = set(MOD.findall(text))
        deps = set()
        for path in USE.findall(text):
            parts = path.split("::")
            if parts[0] == "crate":
                full = parts
            elif parts[0] == "super":
                base = list(module)
                while parts and parts[0] == "super":
                    base, parts = base[:-1], parts[1:]
                full = base + parts
            elif parts[0] == "self":
                full = [*module, *parts[1:]]
            elif parts[0] in children:
                full = [*module, *parts]
            else:
                continue
            for k in range(len(full), 0, -1):
                target = tuple(full[:k])
                if target in files:
                    if target != module:
                        deps.add(target)
                    break
        graph[module] = deps
    return graph


def cycles(graph: dict[tuple[str, ...], set[tuple[str, ...]]]) -> list[list[str]]:
    state: dict[tuple[str, ...], int] = {}
    found: list[list[str]] = []

    def visit(node: tuple[str, ...], stack: list[tuple[str, ...]]) -> None:
        state[node] = 1
        stack.append(node)
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                found.append(["::".join(m) for m in [*stack[stack.index(dep) :], dep]])
            elif not state.get(dep):
                visit(dep, stack)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if not state.get(node):
            visit(node, [])
    return found


@pytest.mark.parametrize("src", SOURCES, ids=lambda p: p.parent.name)
def test_no_import_cycles(src):
    graph = dependencies(src)
    assert len(graph) > 5
    assert cycles(graph) == []


def test_the_checker_sees_a_cycle(tmp_path):
    (tmp_path / "lib.rs").write_text("mod a;\nmod b;\n")
    (tmp_path / "a.rs").write_text("use crate::b::B;\npub struct A;\n")
    (tmp_path / "b.rs").write_text("use super::a::A;\npub struct B;\n")
    assert cycles(dependencies(tmp_path)) == [["crate::a", "crate::b", "crate::a"]]


@pytest.mark.parametrize("src", SOURCES, ids=lambda p: p.parent.name)
def test_library_files_stay_under_500_lines(src):
    long = {
        str(f.relative_to(src)): n
        for f in src.rglob("*.rs")
        if (n := len(f.read_text().splitlines())) > 500
    }
    assert long == {}
