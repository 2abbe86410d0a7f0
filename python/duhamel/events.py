"""Events of a run: instants where a function of the state crosses zero (docs/events.md).

``solve(..., events=[...])`` (and :meth:`duhamel.Prepared.run`) locates every crossing
inside its step by root finding on the step's own interpolant — exact on the linear routes,
of the scheme's order otherwise — and lists them in ``Solution.events``; a terminal event
ends the run at the located instant.

The built-ins (:func:`threshold`, :func:`drift`, :func:`element`) are evaluated on the whole
saved history at once (numpy, no Python call per step); an :class:`Event` of a Python
function is called once per saved step (slower), or once for all of them with
``vectorized=True``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import finite_float, positive_float

__all__ = ["Event", "Occurrence", "drift", "element", "threshold"]


class Event:
    """A zero crossing of ``fn(t, x, v)`` (a float) along a run.

    Parameters
    ----------
    fn : callable
        ``fn(t, x, v) -> float``: ``t`` the time, ``x`` and ``v`` the displacements and
        velocities of the run's output dofs (all dofs by default; ``x[k]`` is dof
        ``dofs[k]``). With ``vectorized=True`` it receives ``t`` of shape ``(n,)`` and ``x``,
        ``v`` of shape ``(n, n_out)`` and returns shape ``(n,)``.
    direction : {0, 1, -1}
        Crossings counted: 0 both, 1 from negative to positive, -1 from positive to negative.
    terminal : bool
        Stop the run at the first occurrence: the solution's last row is that instant.
    name : str, optional
        Shown in the occurrences (default ``"event<index>"``).
    vectorized : bool
        Whether `fn` takes the whole history at once (one Python call instead of one per
        saved step).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(1), 4.0 * np.eye(1))
    >>> up = duhamel.Event(lambda t, x, v: x[0] - 0.5, direction=-1, terminal=True)
    >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=2.0, dt=0.1, x0=[1.0],
    ...                     events=[up])
    >>> bool(abs(sol.t[-1] - np.arccos(0.5) / 2.0) < 1e-12)   # cos(2 t) = 0.5
    True
    """

    def __init__(
        self,
        fn: Callable[..., Any],
        *,
        direction: int = 0,
        terminal: bool = False,
        name: str | None = None,
        vectorized: bool = False,
    ) -> None:
        if not callable(fn):
            raise TypeError(f"`fn` must be callable (t, x, v) -> float, got {type(fn).__name__}")
        if (
            isinstance(direction, bool)
            or not isinstance(direction, int | np.integer)
            or direction not in (0, 1, -1)
        ):
            raise ValueError(f"`direction` must be 0, 1 or -1, got {direction!r}")
        if not isinstance(terminal, bool | np.bool_):
            raise TypeError(f"`terminal` must be True or False, got {terminal!r}")
        if name is not None and not isinstance(name, str):
            raise TypeError(f"`name` must be a string, got {type(name).__name__}")
        if not isinstance(vectorized, bool | np.bool_):
            raise TypeError(f"`vectorized` must be True or False, got {vectorized!r}")
        self.fn = fn
        self.direction = int(direction)
        self.terminal = bool(terminal)
        self.name = name
        self.vectorized = bool(vectorized)

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(name={self.name!r}, direction={self.direction}, "
            f"terminal={self.terminal})"
        )

    def _bind(self, sol: Any) -> None:
        """Checks the event against a solution's saved dofs (built-ins)."""

    def _called(self, *args: Any) -> Any:
        """``fn(*args)``; an exception of the user's function goes on as it is, with a note
        naming the event."""
        try:
            return self.fn(*args)
        except Exception as exc:
            label = "an event" if self.name is None else f"event {self.name!r}"
            exc.add_note(f"raised by the `fn` of {label}, called as fn(t, x, v)")
            raise

    def _returned(self, value: Any, shape: tuple[int, ...]) -> NDArray[np.float64]:
        """What `fn` returned as real numbers of `shape` (``()``: one number), or a
        ValueError naming the event and what it returned."""
        label = "an event" if self.name is None else f"event {self.name!r}"
        try:
            g = np.asarray(value)
        except (TypeError, ValueError):  # a ragged sequence
            g = np.asarray(None)
        if g.dtype.kind not in "fiu":  # None, a string, a bool, complex numbers
            raise ValueError(f"{label}: `fn` must return real numbers, got {type(value).__name__}")
        g = np.asarray(g, dtype=np.float64)
        if g.shape != shape and not (shape == () and g.size == 1):
            what = "one number (a float) per state" if shape == () else f"shape {shape}"
            raise ValueError(f"{label}: `fn` must return {what}, got shape {g.shape}")
        return g.reshape(shape)

    def _values(self, t: NDArray, x: NDArray, v: NDArray, sol: Any) -> NDArray[np.float64]:
        """The event function on every row."""
        if self.vectorized:
            return self._returned(self._called(t, x, v), t.shape)
        return np.array(
            [float(self._returned(self._called(t[k], x[k], v[k]), ())) for k in range(t.size)]
        )

    def _value(self, t: float, x: NDArray, v: NDArray, sol: Any, n: int, s: float) -> float:
        """The event function at one state inside step `n` (at the fraction `s`)."""
        if self.vectorized:
            return float(self._values(np.array([t]), x[None, :], v[None, :], sol)[0])
        return float(self._returned(self._called(t, x, v), ()))


def _column(sol: Any, dof: int, name: str) -> int:
    hits = np.flatnonzero(sol.dofs == dof)
    if hits.size == 0:
        raise ValueError(
            f"`{name}` = {dof} is not among the run's output dofs {sol.dofs.tolist()}: "
            "keep it in `dofs`"
        )
    return int(hits[0])


def _dof(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
        raise ValueError(f"`{name}` must be a dof index (an int >= 0), got {value!r}")
    return int(value)


class _Threshold(Event):
    def __init__(self, dof: int, value: float, **kw: Any) -> None:
        super().__init__(self._scalar, **kw)
        self.dof, self.value = dof, value

    def _scalar(self, t: float, x: NDArray, v: NDArray) -> float:  # pragma: no cover - unused
        raise AssertionError

    def _bind(self, sol: Any) -> None:
        self._col = _column(sol, self.dof, "dof")

    def _values(self, t: NDArray, x: NDArray, v: NDArray, sol: Any) -> NDArray[np.float64]:
        return x[..., self._col] - self.value

    def _value(self, t: float, x: NDArray, v: NDArray, sol: Any, n: int, s: float) -> float:
        return float(x[self._col] - self.value)


class _Drift(Event):
    def __init__(self, i: int, j: int | None, limit: float, height: float, **kw: Any) -> None:
        super().__init__(_Threshold._scalar, **kw)
        self.i, self.j, self.limit, self.height = i, j, limit, height

    def _bind(self, sol: Any) -> None:
        self._ci = _column(sol, self.i, "i")
        self._cj = None if self.j is None else _column(sol, self.j, "j")

    def _values(self, t: NDArray, x: NDArray, v: NDArray, sol: Any) -> NDArray[np.float64]:
        d = x[..., self._ci] if self._cj is None else x[..., self._ci] - x[..., self._cj]
        return np.abs(d) / self.height - self.limit

    def _value(self, t: float, x: NDArray, v: NDArray, sol: Any, n: int, s: float) -> float:
        return float(self._values(np.array([t]), x[None, :], v[None, :], sol)[0])


class _Element(Event):
    def __init__(self, k: int, quantity: str, value: float, **kw: Any) -> None:
        super().__init__(_Threshold._scalar, **kw)
        self.k, self.quantity, self.value = k, quantity, value

    def _bind(self, sol: Any) -> None:
        if self.k >= len(sol.elements):
            raise ValueError(f"`k` = {self.k}: the run has {len(sol.elements)} force elements")
        el = sol.elements[self.k].element
        if self.quantity == "deformation":
            if not hasattr(el, "i"):
                raise ValueError(
                    f"element {self.k} ({type(el).__name__}) has no single deformation "
                    "x_i - x_j; use quantity='force' or an Event of its dofs"
                )
            self._ci = _column(sol, int(el.i), "the element's i")
            j = getattr(el, "j", None)
            self._cj = None if j is None else _column(sol, int(j), "the element's j")
        else:
            force = sol.elements[self.k].axial_force
            if force.ndim != 1:
                raise ValueError(
                    f"element {self.k} ({type(el).__name__}) has no single axial force"
                )
            self._force = force

    def _values(self, t: NDArray, x: NDArray, v: NDArray, sol: Any) -> NDArray[np.float64]:
        if self.quantity == "deformation":
            d = x[..., self._ci] if self._cj is None else x[..., self._ci] - x[..., self._cj]
            return d - self.value
        return self._force[: t.size] - self.value

    def _value(self, t: float, x: NDArray, v: NDArray, sol: Any, n: int, s: float) -> float:
        if self.quantity == "deformation":
            d = x[self._ci] if self._cj is None else x[self._ci] - x[self._cj]
            return float(d - self.value)
        # The force inside the step: linear between the saved steps (second order).
        f = self._force
        return float((1.0 - s) * f[n] + s * f[n + 1] - self.value)


def _options(direction: int, terminal: bool, name: str | None) -> dict[str, Any]:
    return {"direction": direction, "terminal": terminal, "name": name}


def threshold(
    dof: int,
    value: float,
    *,
    direction: int = 0,
    terminal: bool = False,
    name: str | None = None,
) -> Event:
    """The displacement of `dof` reaching `value`: ``x[dof] - value`` crosses zero.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(1), np.eye(1))
    >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=4.0, dt=0.5, x0=[1.0],
    ...                     events=[duhamel.events.threshold(0, 0.0)])
    >>> bool(abs(sol.events[0].time - np.pi / 2) < 1e-12)        # cos t = 0
    True
    """
    ev = _Threshold(_dof(dof, "dof"), finite_float(value, "value"),
                    **_options(direction, terminal, name))  # fmt: skip
    ev.name = name if name is not None else f"x[{dof}] = {value:g}"
    return ev


def drift(
    i: int,
    j: int | None,
    limit: float,
    height: float = 1.0,
    *,
    direction: int = 1,
    terminal: bool = False,
    name: str | None = None,
) -> Event:
    """The drift ratio ``|x_i - x_j| / height`` reaching `limit` (`j` None: against the
    support). By default only the crossings upward count (``direction=1``).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(1), np.eye(1))
    >>> stop = duhamel.events.drift(0, None, 0.5, height=2.0, terminal=True)
    >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=3.0, dt=0.1, v0=[2.0],
    ...                     events=[stop])
    >>> bool(abs(sol.t[-1] - np.arcsin(0.5)) < 1e-12)         # |2 sin t| / 2 = 0.5
    True
    """
    j = None if j is None else _dof(j, "j")
    if j is not None and j == _dof(i, "i"):
        raise ValueError(
            f"`j` must differ from `i` (both are {j}): the drift of a dof against itself is "
            "always 0; pass the dof of the floor below, or j=None for the drift against the "
            "support"
        )
    ev = _Drift(_dof(i, "i"), j, finite_float(limit, "limit"), positive_float(height, "height"),
                **_options(direction, terminal, name))  # fmt: skip
    ev.name = name if name is not None else f"drift({i}, {j}) = {limit:g}"
    return ev


def element(
    k: int,
    quantity: str,
    value: float,
    *,
    direction: int = 0,
    terminal: bool = False,
    name: str | None = None,
) -> Event:
    """Element `k`'s (in the order of ``sol.elements``) deformation ``x_i - x_j`` or axial
    force reaching `value`. The deformation inside a step is the interpolant's; the force
    is interpolated linearly between the saved steps (second order).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(1), np.eye(1))
    >>> _ = s.add(duhamel.elements.Gap(0, None, gap=0.5, k=100.0))
    >>> contact = duhamel.events.element(0, "deformation", -0.5, direction=-1)
    >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=3.0, dt=0.01, x0=[1.0],
    ...                     events=[contact])
    >>> bool(abs(sol.events[0].time - 2 * np.pi / 3) < 1e-4)    # cos t = -0.5
    True
    """
    if not isinstance(quantity, str) or quantity not in ("deformation", "force"):
        raise ValueError(f"`quantity` must be 'deformation' or 'force', got {quantity!r}")
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or k < 0:
        raise ValueError(f"`k` must be an element index (an int >= 0), got {k!r}")
    ev = _Element(int(k), quantity, finite_float(value, "value"),
                  **_options(direction, terminal, name))  # fmt: skip
    ev.name = name if name is not None else f"element {k} {quantity} = {value:g}"
    return ev


@dataclass(frozen=True)
class Occurrence:
    """One located crossing of an event.

    Attributes
    ----------
    name : str
        The event's name.
    index : int
        Which event (its position in ``events``).
    time : float
        The located instant.
    x, v : ndarray, shape (n_out,)
        Displacements and velocities of the output dofs there.
    terminal : bool
        Whether the run stopped there.
    """

    name: str
    index: int
    time: float
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    terminal: bool = False
    _step: tuple[int, float] = field(default=(0, 0.0), repr=False, compare=False)
