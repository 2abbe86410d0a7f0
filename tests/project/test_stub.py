"""``python/duhamel/_core.pyi`` describes the built ``duhamel._core`` exactly (issue 22).

Every public name of the native module — functions, classes, their static, class and
instance methods, properties and constructors (``#[new]``) — is in the stub with the same
kind and the same parameters (names, kinds, which have defaults and, where the stub writes
one, the default's value), read from the ``__text_signature__`` that PyO3 gives; and the stub
names nothing that the module lacks, except type aliases and ``@type_check_only`` helper
classes (none now: every input is a typed class of the module). The stub is also checked for
itself: it parses, every annotation names something defined or imported in it, every
parameter and return is annotated, and no parameter is a bare ``Any``.

On failure the message lists every difference, with the line to paste into the stub for a
missing binding. (An AST comparison rather than mypy's stubtest: no extra dependency, and
messages that say what to change.)
"""

from __future__ import annotations

import ast
import builtins
import inspect
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from duhamel import _core

STUB = Path(_core.__file__).with_name("_core.pyi")

#: Runtime dunders that need no stub entry (object's, or module/class bookkeeping).
IGNORED_DUNDERS = frozenset(
    {
        "__doc__",
        "__signature__",
        "__module__",
        "__repr__",
        "__str__",
        "__hash__",
        "__dict__",
        "__weakref__",
        "__qualname__",
        "__firstlineno__",
        "__static_attributes__",
        "__annotations__",
        "__loader__",
        "__name__",
        "__package__",
        "__spec__",
        "__file__",
        "__builtins__",
        "__cached__",
        "__path__",
        "__all__",
    }
)


@dataclass
class Param:
    name: str
    kind: str  # inspect.Parameter kind name
    default: str | None  # None: no default; "...": any default; else the default's repr

    def render(self) -> str:
        return self.name if self.default is None else f"{self.name}={self.default}"


@dataclass
class Entry:
    kind: str  # function, class, staticmethod, classmethod, method, property, attribute
    params: list[Param] | None = None  # None: unknown (no text signature)
    members: dict[str, Entry] = field(default_factory=dict)
    stub_only_ok: bool = False  # an alias or a @type_check_only class
    final: bool = False  # a class that cannot be subclassed


def render(params: list[Param] | None) -> str:
    if params is None:
        return "(?)"
    out, seen_kw = [], False
    for i, p in enumerate(params):
        if p.kind == "KEYWORD_ONLY" and not seen_kw:
            out.append("*")
            seen_kw = True
        if p.kind == "VAR_POSITIONAL":
            out.append("*" + p.name)
            seen_kw = True
            continue
        if p.kind == "VAR_KEYWORD":
            out.append("**" + p.name)
            continue
        out.append(p.render())
        after = params[i + 1] if i + 1 < len(params) else None
        if p.kind == "POSITIONAL_ONLY" and (after is None or after.kind != "POSITIONAL_ONLY"):
            out.append("/")
    return "(" + ", ".join(out) + ")"


# ---------------------------------------------------------------------------- the module
def runtime_params(obj: object, drop_first: bool) -> list[Param] | None:
    if getattr(obj, "__text_signature__", None) is None:
        return None
    try:
        sig = inspect.signature(obj)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None
    params = [
        Param(
            p.name,
            p.kind.name,
            None if p.default is inspect.Parameter.empty else repr(p.default),
        )
        for p in sig.parameters.values()
    ]
    return params[1:] if drop_first and params else params


#: Py_TPFLAGS_BASETYPE: the class can be subclassed (PyO3: ``#[pyclass(subclass)]``).
BASETYPE = 1 << 10


def runtime_class(cls: type) -> Entry:
    entry = Entry("class", final=not cls.__flags__ & BASETYPE)
    for name, raw in vars(cls).items():
        if name in IGNORED_DUNDERS:
            continue
        if name == "__new__":
            # PyO3's #[new]: the signature is the class's own text signature
            entry.members[name] = Entry("constructor", runtime_params(cls, drop_first=False))
        elif isinstance(raw, staticmethod):
            entry.members[name] = Entry("staticmethod", runtime_params(getattr(cls, name), False))
        elif isinstance(raw, classmethod) or (
            inspect.isbuiltin(getattr(cls, name))
            and getattr(getattr(cls, name), "__self__", None) is cls
        ):
            entry.members[name] = Entry("classmethod", runtime_params(getattr(cls, name), False))
        elif inspect.isgetsetdescriptor(raw) or inspect.ismemberdescriptor(raw):
            entry.members[name] = Entry("property")
        elif isinstance(raw, property):
            entry.members[name] = Entry("property")
        elif callable(raw):
            entry.members[name] = Entry("method", runtime_params(raw, drop_first=True))
        else:
            entry.members[name] = Entry("attribute")
    return entry


def runtime_api() -> dict[str, Entry]:
    api = {}
    for name in dir(_core):
        if name in IGNORED_DUNDERS:
            continue
        obj = getattr(_core, name)
        if isinstance(obj, type):
            api[name] = runtime_class(obj)
        elif callable(obj):
            api[name] = Entry("function", runtime_params(obj, drop_first=False))
        else:
            api[name] = Entry("attribute")
    return api


# ---------------------------------------------------------------------------- the stub
def decorator_names(node: ast.FunctionDef | ast.ClassDef) -> set[str]:
    names = set()
    for d in node.decorator_list:
        target = d.func if isinstance(d, ast.Call) else d
        names.add(target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", ""))
    return names


def stub_params(fn: ast.FunctionDef, drop_first: bool) -> list[Param]:
    a = fn.args
    positional = [(x, "POSITIONAL_ONLY") for x in a.posonlyargs] + [
        (x, "POSITIONAL_OR_KEYWORD") for x in a.args
    ]
    defaults: list[ast.expr | None] = [None] * (len(positional) - len(a.defaults)) + list(
        a.defaults
    )
    params = [
        Param(arg.arg, kind, default_text(d))
        for (arg, kind), d in zip(positional, defaults, strict=True)
    ]
    if a.vararg:
        params.append(Param(a.vararg.arg, "VAR_POSITIONAL", None))
    params += [
        Param(arg.arg, "KEYWORD_ONLY", default_text(d))
        for arg, d in zip(a.kwonlyargs, a.kw_defaults, strict=True)
    ]
    if a.kwarg:
        params.append(Param(a.kwarg.arg, "VAR_KEYWORD", None))
    return params[1:] if drop_first and params else params


def default_text(node: ast.expr | None) -> str | None:
    if node is None:
        return None
    if isinstance(node, ast.Constant) and node.value is Ellipsis:
        return "..."
    try:
        return repr(ast.literal_eval(node))
    except ValueError:
        return "..."


def stub_class(node: ast.ClassDef) -> Entry:
    decorators = decorator_names(node)
    entry = Entry(
        "class", stub_only_ok="type_check_only" in decorators, final="final" in decorators
    )
    for item in node.body:
        if isinstance(item, ast.FunctionDef):
            decorators = decorator_names(item)
            if "property" in decorators or "setter" in decorators:
                entry.members[item.name] = Entry("property")
            elif "staticmethod" in decorators:
                entry.members[item.name] = Entry("staticmethod", stub_params(item, False))
            elif "classmethod" in decorators:
                entry.members[item.name] = Entry("classmethod", stub_params(item, True))
            elif item.name in ("__new__", "__init__"):
                entry.members["__new__"] = Entry("constructor", stub_params(item, True))
            else:
                entry.members[item.name] = Entry("method", stub_params(item, True))
        elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
            entry.members[item.target.id] = Entry("property")
    return entry


def stub_api(tree: ast.Module) -> dict[str, Entry]:
    api = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            api[node.name] = Entry("function", stub_params(node, False))
        elif isinstance(node, ast.ClassDef):
            api[node.name] = stub_class(node)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            alias = node.value is not None and "TypeAlias" in ast.unparse(node.annotation)
            api[node.target.id] = Entry("attribute", stub_only_ok=alias)
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    api[target.id] = Entry("attribute", stub_only_ok=True)
        elif type(node).__name__ == "TypeAlias":  # Python >= 3.12
            api[node.name.id] = Entry("attribute", stub_only_ok=True)  # type: ignore[attr-defined]
    return api


# ---------------------------------------------------------------------------- comparison
SAME_KIND = {("property", "attribute"), ("attribute", "property")}


def skeleton(name: str, entry: Entry, indent: str = "") -> str:
    """The stub lines to paste for a runtime entry (annotations to fill in)."""
    sig = render(entry.params)
    if entry.kind == "function":
        return f"{indent}def {name}{sig} -> ...: ..."
    if entry.kind == "staticmethod":
        return f"{indent}@staticmethod\n{indent}def {name}{sig} -> ...: ..."
    if entry.kind == "classmethod":
        return f"{indent}@classmethod\n{indent}def {name}(cls, {sig[1:]} -> ...: ..."
    if entry.kind == "constructor":
        return f"{indent}def __new__(cls, {sig[1:]} -> Self: ..."
    if entry.kind == "method":
        return f"{indent}def {name}(self, {sig[1:]} -> ...: ...".replace("(self, )", "(self)")
    if entry.kind == "property":
        return f"{indent}@property\n{indent}def {name}(self) -> ...: ..."
    if entry.kind == "class":
        body = [skeleton(m, e, "    ") for m, e in entry.members.items()] or ["    ..."]
        return f"class {name}:\n" + "\n".join(body)
    return f"{indent}{name}: ..."


def compare(path: str, runtime: Entry, stub: Entry, problems: list[str]) -> None:
    if runtime.kind != stub.kind and (runtime.kind, stub.kind) not in SAME_KIND:
        problems.append(f"{path}: a {runtime.kind} in the module, a {stub.kind} in the stub")
        return
    if runtime.kind == "class" and runtime.final != stub.final:
        problems.append(
            f"{path}: "
            + (
                "cannot be subclassed: mark it @final in the stub"
                if runtime.final
                else "can be subclassed: remove @final from the stub"
            )
        )
    if runtime.params is not None and stub.params is not None:
        if [(p.name, p.kind) for p in runtime.params] != [(p.name, p.kind) for p in stub.params]:
            problems.append(
                f"{path}: parameters differ: module {render(runtime.params)}, "
                f"stub {render(stub.params)}"
            )
        else:
            for r, s in zip(runtime.params, stub.params, strict=True):
                if (r.default is None) != (s.default is None) or (
                    s.default not in (None, "...") and s.default != r.default
                ):
                    problems.append(
                        f"{path}: default of `{r.name}`: module {r.default or 'none'}, "
                        f"stub {s.default or 'none'} (module {render(runtime.params)})"
                    )
    for name, member in runtime.members.items():
        if name not in stub.members:
            problems.append(
                f"{path}.{name} ({member.kind}) is missing in the stub; add to class "
                f"{path}:\n{skeleton(name, member, '    ')}"
            )
        else:
            compare(f"{path}.{name}", member, stub.members[name], problems)
    for name in stub.members:
        if name not in runtime.members and not stub.stub_only_ok:
            problems.append(f"{path}.{name} is in the stub but not in the module: remove it")


def stub_tree() -> ast.Module:
    return ast.parse(STUB.read_text(encoding="utf-8"), filename=str(STUB))


def test_stub_names_every_binding_with_its_parameters() -> None:
    runtime, stub = runtime_api(), stub_api(stub_tree())
    problems: list[str] = []
    for name, entry in runtime.items():
        if name not in stub:
            problems.append(
                f"{name} ({entry.kind}) is missing in the stub; add:\n{skeleton(name, entry)}"
            )
        else:
            compare(name, entry, stub[name], problems)
    for name, entry in stub.items():
        if name not in runtime and not entry.stub_only_ok:
            problems.append(
                f"{name} is in the stub but not in the module: remove it (or, for a stub-only "
                "helper, make it a type alias or a @type_check_only class)"
            )
    assert not problems, (
        f"{STUB} does not match the built duhamel._core ({_core.__file__}); "
        f"{len(problems)} difference(s):\n- " + "\n- ".join(problems)
    )


def test_every_parameter_has_a_signature_to_check() -> None:
    """PyO3 gives every function and method a text signature; without it the comparison
    above would check names only."""
    missing = [
        f"{name}.{m}" if m else name
        for name, entry in runtime_api().items()
        for m, e in [("", entry), *entry.members.items()]
        if e.kind in ("function", "staticmethod", "classmethod", "method", "constructor")
        and e.params is None
    ]
    assert not missing, f"no __text_signature__ at runtime: {missing}"


def annotations(tree: ast.Module) -> list[tuple[str, ast.expr | None]]:
    """(where, annotation) of every parameter and return of every function in the stub."""
    out: list[tuple[str, ast.expr | None]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    item.name = f"{node.name}.{item.name}"
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            a = node.args
            args = [*a.posonlyargs, *a.args, *a.kwonlyargs]
            for arg in args:
                if arg.arg not in ("self", "cls"):
                    out.append((f"{node.name}({arg.arg})", arg.annotation))
            out.append((f"{node.name} -> return", node.returns))
    return out


def test_stub_is_fully_and_soundly_annotated() -> None:
    tree = stub_tree()
    defined = set(dir(builtins))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            defined |= {(a.asname or a.name).split(".")[0] for a in node.names}
        elif isinstance(node, ast.ClassDef | ast.FunctionDef):
            defined.add(node.name)
        elif isinstance(node, ast.Assign):
            defined |= {t.id for t in node.targets if isinstance(t, ast.Name)}
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            defined.add(node.target.id)
    problems = []
    for where, annotation in annotations(tree):
        if annotation is None:
            problems.append(f"{where}: not annotated")
            continue
        if isinstance(annotation, ast.Name) and annotation.id == "Any" and "return" not in where:
            problems.append(f"{where}: a bare Any (name the type, or a Protocol of what is read)")
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id not in defined:
            problems.append(
                f"line {node.lineno}: `{node.id}` is not defined or imported in the stub"
            )
    assert not problems, f"{STUB}:\n- " + "\n- ".join(problems)


@pytest.mark.parametrize(
    "entry", ["Element.replace", "bilinear_peak", "RunResult.t", "ModalModel.run", "Grid.__new__"]
)
def test_the_comparison_sees_a_difference(entry: str) -> None:
    """The check itself: a stub with one parameter, method, property or constructor taken
    out fails."""
    tree = stub_tree()
    owner, _, member = entry.rpartition(".")
    for node in tree.body:
        if owner and isinstance(node, ast.ClassDef) and node.name == owner:
            node.body = [n for n in node.body if getattr(n, "name", None) != member]
        if not owner and isinstance(node, ast.FunctionDef) and node.name == member:
            node.args.args = node.args.args[:-1]
    runtime, stub = runtime_api(), stub_api(tree)
    problems: list[str] = []
    for name, e in runtime.items():
        if name in stub:
            compare(name, e, stub[name], problems)
    assert [p for p in problems if p.startswith(entry + " ") or p.startswith(entry + ":")], problems
