"""Old spellings of the previous release, kept for this one with a ``DeprecationWarning``
that names the new spelling (docs/models.md, "Where things act").

The one helper of the Python classes (the loads; the elements' old spellings are declared in
their Rust definitions and mapped by the binding): :func:`old_spellings` makes a class also
accept the previous release's positional order and parameter names, :func:`deprecated`
warns at the user's call.
"""

from __future__ import annotations

import functools
import inspect
import warnings
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

__all__ = ["deprecated", "old_spellings"]

T = TypeVar("T", bound=type)


def deprecated(message: str, stacklevel: int = 2) -> None:
    """A ``DeprecationWarning`` with `message`, attributed to the caller `stacklevel` frames
    up (2: the caller of the function that calls this one).

    Examples
    --------
    >>> import warnings
    >>> from duhamel._engine.spellings import deprecated
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     deprecated("`old` is deprecated, use `new`")
    >>> str(caught[0].message)
    '`old` is deprecated, use `new`'
    """
    warnings.warn(message, DeprecationWarning, stacklevel=stacklevel + 1)


def old_spellings(
    *,
    positional: tuple[str, ...],
    renamed: Mapping[str, str] | None = None,
    merged: Mapping[str, tuple[str, ...]] | None = None,
    defaults: Mapping[str, Any] | None = None,
) -> Callable[[T], T]:
    """Class decorator: the class also takes the previous release's spellings, each with a
    ``DeprecationWarning`` naming the new signature.

    Parameters
    ----------
    positional : tuple of str
        The previous release's parameters in their positional order (physical parameters
        given by position, now keyword-only); names as the previous release had them.
    renamed : mapping, optional
        Old parameter name -> new name.
    merged : mapping, optional
        New parameter -> the old ones it gathers into a tuple (``{"dofs": ("dof_x",
        "dof_y")}``); all of them must be given.
    defaults : mapping, optional
        The previous release's defaults of parameters that are now required (a physical
        value has no default): a call without one still runs with it, warned.

    Examples
    --------
    >>> import warnings
    >>> from dataclasses import dataclass, field
    >>> from duhamel._engine.spellings import old_spellings
    >>> @old_spellings(positional=("dof", "amplitude"))
    ... @dataclass(frozen=True)
    ... class Force:
    ...     dof: int
    ...     amplitude: float = field(kw_only=True)
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     old = Force(2, 5.0)
    >>> old == Force(2, amplitude=5.0), str(caught[0].message)
    (True, 'Force(dof, amplitude): this positional form is deprecated; the dofs come first and the physical parameters are keyword-only: Force(dof, *, amplitude)')
    """  # noqa: E501
    renames = dict(renamed or {})
    merges = {new: tuple(old) for new, old in (merged or {}).items()}
    required = dict(defaults or {})

    def decorate(cls: T) -> T:
        init = cls.__init__  # type: ignore[misc]
        params = list(inspect.signature(init).parameters.values())[1:]
        new_positional = tuple(
            p.name for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
        )
        n_positional = len(new_positional)
        shown = _unannotated(cls.__name__, params)
        gathered = {old: new for new, group in merges.items() for old in group}
        # the old keywords and the required ones, as sets: a call in the new spelling is
        # told apart by two set operations (no generator per call)
        watched = frozenset(renames) | frozenset(gathered)
        needed = frozenset(required)

        @functools.wraps(init)
        def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
            if (
                len(args) > n_positional
                or (watched and not watched.isdisjoint(kwargs))
                or (needed and not needed <= kwargs.keys())
            ):
                kwargs = _translate(cls.__name__, shown, args, kwargs, positional, renames,
                                    merges, required, new_positional)  # fmt: skip
                args = ()
            init(self, *args, **kwargs)

        cls.__init__ = __init__  # type: ignore[misc]
        return cls

    return decorate


def _unannotated(name: str, params: list[inspect.Parameter]) -> str:
    """``Name(dof, *, amplitude, t0=0.0)``: the signature as the docs write it."""
    parts: list[str] = []
    star = False
    for p in params:
        if p.kind is p.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        default = "" if p.default is p.empty else f"={p.default!r}"
        parts.append(f"{p.name}{default}")
    return f"{name}({', '.join(parts)})"


def _translate(
    name: str,
    shown: str,
    args: tuple[Any, ...],
    kwargs: dict[str, Any],
    positional: tuple[str, ...],
    renames: dict[str, str],
    merges: dict[str, tuple[str, ...]],
    required: dict[str, Any],
    new_positional: tuple[str, ...],
) -> dict[str, Any]:
    """The keyword arguments of the new signature for an old call (warning once per old
    spelling, at the user's call: three frames up)."""
    out = dict(kwargs)
    from_position: set[str] = set()
    if args and len(args) <= len(new_positional):  # the new positional form
        for key, value in zip(new_positional, args, strict=False):
            if key in out:
                raise TypeError(f"{name}() got multiple values for `{key}`: {shown}")
            out[key] = value
        args = ()
    if args:
        if len(args) > len(positional):
            raise TypeError(
                f"{name}() takes at most {len(positional)} positional arguments "
                f"({len(args)} given): {shown}"
            )
        for key, value in zip(positional, args, strict=False):
            if key in out:
                raise TypeError(f"{name}() got multiple values for `{key}`: {shown}")
            out[key] = value
        from_position = set(positional[: len(args)])
        deprecated(
            f"{name}({', '.join(positional[: len(args)])}): this positional form is deprecated; "
            f"the dofs come first and the physical parameters are keyword-only: {shown}",
            stacklevel=3,
        )
    for old, new in renames.items():
        if old in out:
            if new in out:
                raise TypeError(f"{name}() got both `{old}` and `{new}`: {shown}")
            out[new] = out.pop(old)
            if old not in from_position:
                deprecated(f"{name}: `{old}` is deprecated, use `{new}`: {shown}", stacklevel=3)
    for new, group in merges.items():
        given = [old for old in group if old in out]
        if not given:
            continue
        if new in out:
            raise TypeError(f"{name}() got both `{given[0]}` and `{new}`: {shown}")
        missing = [old for old in group if old not in out]
        if missing:
            raise TypeError(
                f"{name}() got `{given[0]}` without `{missing[0]}`: give both as "
                f"`{new}`=({', '.join(group)}): {shown}"
            )
        out[new] = tuple(out.pop(old) for old in group)
        if not set(given) <= from_position:
            deprecated(
                f"{name}: `{'`, `'.join(group)}` are deprecated, use `{new}`=({', '.join(group)}): "
                f"{shown}",
                stacklevel=3,
            )
    for key, value in required.items():
        if key not in out:
            out[key] = value
            deprecated(
                f"{name}: `{key}` is required (a physical value has no default); the previous "
                f"release's default {value!r} is used for now: {shown}",
                stacklevel=3,
            )
    return out
