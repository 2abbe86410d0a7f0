"""Time-dependent loads ``f(t)``, added to a model with ``System.add_load``.

Built-in loads are a fixed spatial pattern times a scalar time function, both evaluated in
Rust during the time loop. :class:`Callable` is the escape hatch: a Python function of time
returning the whole load vector, called once per evaluation time.

Within each step the time loop represents a load by the parabola through its values at the
start, middle and end of the step; this is exact for loads that are polynomials of degree
<= 2 in time within each step (constant, ramps, and :class:`Tabulated` records whose sample
times fall on the step grid) and fourth-order accurate otherwise (e.g. :class:`Harmonic`).
A :class:`Step` is integrated exactly even when its jump falls inside a step, and so are the
jumps at the ends of a :class:`Tabulated` record.

:class:`Unbalance` is the rotating force of an eccentric mass driven by a speed law
(:mod:`duhamel.speed`; :class:`ConstantSpeed` and :class:`LinearRunUp` are re-exported here).
"""

from __future__ import annotations

from collections.abc import Callable as CallableT
from collections.abc import Sequence
from dataclasses import KW_ONLY, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.labels import is_label, resolve
from duhamel._engine.protocols import Model
from duhamel._engine.spellings import deprecated, old_spellings
from duhamel._engine.validate import as_float_array, dof_index, finite_float
from duhamel.speed import ConstantSpeed, LinearRunUp, SpeedLaw, as_speed_law

__all__ = [
    "BaseAcceleration",
    "Callable",
    "ConstantSpeed",
    "Dof",
    "Harmonic",
    "LinearRunUp",
    "Load",
    "SpeedLaw",
    "Step",
    "Tabulated",
    "Unbalance",
    "support_terms",
]


#: Where a load acts: a dof index or a dof label (a name, or a ``(node, component)`` pair),
#: resolved when the load is added to a system.
Dof = int | str | tuple[int, str]


def _finite(value: Any, name: str) -> float:
    """`value` as a finite float (the one numeric validator: any real or numpy number)."""
    return finite_float(value, name)


def _table(t: ArrayLike, values: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    ts = as_float_array(t, "t", ndim=1)
    vs = as_float_array(values, "values", ndim=1)
    if ts.size < 2:
        raise ValueError(f"`t` needs at least two samples, got {ts.size}")
    if vs.shape != ts.shape:
        raise ValueError(f"`values` must have the shape of `t` {ts.shape}, got {vs.shape}")
    if np.any(np.diff(ts) <= 0):
        i = int(np.argmax(np.diff(ts) <= 0))
        raise ValueError(
            f"`t` must be strictly increasing (t[{i}] = {ts[i]}, t[{i + 1}] = {ts[i + 1]})"
        )
    return ts, vs


def _table_eval(t: NDArray, ts: NDArray, vs: NDArray, hold: bool) -> NDArray:
    """Right-continuous: 0 before ``ts[0]``; from ``ts[-1]`` on 0, or the last value if `hold`."""
    out = np.interp(t, ts, vs)
    out[t < ts[0]] = 0.0
    if not hold:
        out[t >= ts[-1]] = 0.0
    return out


class Load:
    """Base class: ``f(t) = pattern * s(t)``."""

    def _validate(self, system: Model) -> None:
        self._pattern(system)

    def _pattern(self, system: Model) -> NDArray[np.float64]:  # pragma: no cover - abstract
        raise NotImplementedError

    def _time(self) -> _core.TimeFunction:  # pragma: no cover - abstract
        """The time function ``s(t)`` as the core evaluates it."""
        raise NotImplementedError

    def _scalar(self, t: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover
        raise NotImplementedError

    def _terms(self, system: Model) -> list[_core.Load]:
        """The load as the core's terms ``pattern * s(t)``, physical patterns (one for a
        pattern times one time function; :class:`Unbalance` has two)."""
        return [_core.Load(pattern, time) for pattern, time in self._parts(system)]

    def _parts(self, system: Model) -> list[tuple[NDArray[np.float64], _core.TimeFunction]]:
        """:meth:`_terms` as ``(pattern, time function)`` pairs, before the core's ``Load``
        is made (what a projection on the modes reads)."""
        return [(np.ascontiguousarray(self._pattern(system), dtype=np.float64), self._time())]

    def evaluate(self, system: Model, t: ArrayLike) -> NDArray[np.float64]:
        """The load vectors at times `t`, shape ``(len(t), n_dof)`` (or ``(n_dof,)``).

        Parameters
        ----------
        system : System
            The model the load acts on.
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            Load vectors, one row per time.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> sys = duhamel.System(np.eye(2), np.diag([1.0, 4.0]))
        >>> duhamel.loads.Step(1, amplitude=5.0, t0=1.0).evaluate(sys, [0.0, 2.0])
        array([[0., 0.],
               [0., 5.]])
        """
        ts = np.asarray(t, dtype=np.float64)
        s = self._scalar(np.atleast_1d(ts))
        out = np.outer(s, self._pattern(system))
        return out[0] if ts.ndim == 0 else out


def _index(system: Model, dof: Any, name: str) -> int:
    """`dof` (an index, or a label of `system`) as an index of `system`."""
    return dof_index(resolve(system, dof, name), name, system.n_dof)


def _unit(system: Model, dof: Any, amplitude: float) -> NDArray[np.float64]:
    p = np.zeros(system.n_dof)
    p[_index(system, dof, "dof")] = amplitude
    return p


def _table_time(t: NDArray, values: NDArray, hold: bool) -> _core.TimeFunction:
    return _core.TimeFunction.table(
        np.ascontiguousarray(t, dtype=np.float64),
        np.ascontiguousarray(values, dtype=np.float64),
        bool(hold),
    )


@old_spellings(positional=("dof", "amplitude", "t0"))
@dataclass(frozen=True)
class Step(Load):
    """A force `amplitude` switched on at `t0` on the degree of freedom `dof` (Heaviside):
    ``Step(dof, *, amplitude, t0=0.0)``.

    Integrated exactly, also when `t0` falls inside a time step.

    Examples
    --------
    >>> import duhamel
    >>> load = duhamel.loads.Step(0, amplitude=1e3, t0=0.05)
    """

    dof: Dof
    _: KW_ONLY
    amplitude: float
    t0: float = 0.0

    def __post_init__(self) -> None:
        _finite(self.amplitude, "amplitude")
        _finite(self.t0, "t0")

    def _pattern(self, system: Model) -> NDArray[np.float64]:
        return _unit(system, self.dof, float(self.amplitude))

    def _time(self) -> _core.TimeFunction:
        return _core.TimeFunction.step(float(self.t0))

    def _scalar(self, t: NDArray) -> NDArray:
        return (t >= self.t0).astype(np.float64)


@old_spellings(positional=("dof", "amplitude", "omega", "phase"))
@dataclass(frozen=True)
class Harmonic(Load):
    """``amplitude * sin(omega t + phase)`` on the degree of freedom `dof`:
    ``Harmonic(dof, *, amplitude, omega, phase=0.0)``.

    Examples
    --------
    >>> import duhamel
    >>> load = duhamel.loads.Harmonic(3, amplitude=10.0, omega=2 * 3.14159 * 5)
    """

    dof: Dof
    _: KW_ONLY
    amplitude: float
    omega: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        for name in ("amplitude", "omega", "phase"):
            _finite(getattr(self, name), name)

    def _pattern(self, system: Model) -> NDArray[np.float64]:
        return _unit(system, self.dof, float(self.amplitude))

    def _time(self) -> _core.TimeFunction:
        return _core.TimeFunction.harmonic(float(self.omega), float(self.phase))

    def _scalar(self, t: NDArray) -> NDArray:
        return np.sin(self.omega * t + self.phase)


@old_spellings(positional=("dof", "t", "values", "hold"))
@dataclass(frozen=True, eq=False)
class Tabulated(Load):
    """A force history on the degree of freedom `dof`, linear between samples ``(t,
    values)``: ``Tabulated(dof, *, t, values, hold=False)``.

    Zero before ``t[0]``; from ``t[-1]`` on zero (a record that has ended), or the last
    value when ``hold=True``. Loads are right-continuous: at a jump, the value after it.
    Exact when the sample times fall on the step grid. The jumps at the first and last
    samples are integrated exactly wherever they fall (also when the record's times miss
    the grid, if only by a rounding); an interior sample off the grid is a kink inside a
    step, represented by the step's parabola.

    Examples
    --------
    >>> import duhamel
    >>> ramp = duhamel.loads.Tabulated(0, t=[0.0, 1.0], values=[0.0, 100.0], hold=True)
    """

    dof: Dof
    _: KW_ONLY
    t: NDArray[np.float64]
    values: NDArray[np.float64]
    hold: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.hold, bool | np.bool_):
            raise TypeError(f"`hold` must be True or False, got {self.hold!r}")
        ts, vs = _table(self.t, self.values)
        object.__setattr__(self, "t", ts)
        object.__setattr__(self, "values", vs)

    def _pattern(self, system: Model) -> NDArray[np.float64]:
        return _unit(system, self.dof, 1.0)

    def _time(self) -> _core.TimeFunction:
        return _table_time(self.t, self.values, self.hold)

    def _scalar(self, t: NDArray) -> NDArray:
        return _table_eval(t, self.t, self.values, self.hold)


@old_spellings(positional=("direction_vector", "t", "values"))
@dataclass(frozen=True, eq=False)
class BaseAcceleration(Load):
    """Support (ground) acceleration ``a_g(t)``: the load ``f = -M r a_g(t)``;
    ``BaseAcceleration(direction_vector, *, t, values)``.

    ``direction_vector`` is the influence vector ``r`` (the displacement of each degree of
    freedom for a unit rigid support displacement, e.g. ones on the horizontal dofs of a
    shear building), or the name of a component of a labelled system (``"ux"``: ones on
    the dofs labelled ``(node, "ux")``, set by :meth:`duhamel.System.add_load`). The
    response is relative to the support. ``a_g`` is linear between
    the samples ``(t, values)`` and zero outside them (the record has ended).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> quake = duhamel.loads.BaseAcceleration(np.ones(5), t=t, values=2.9 * np.sin(8 * t))
    """

    direction_vector: NDArray[np.float64]
    _: KW_ONLY
    t: NDArray[np.float64]
    values: NDArray[np.float64]

    def __post_init__(self) -> None:
        # a component name ("ux") of a labelled system: ones on its dofs, set when added
        r = (
            self.direction_vector
            if isinstance(self.direction_vector, str)
            else as_float_array(self.direction_vector, "direction_vector", ndim=1)
        )
        ts, vs = _table(self.t, self.values)
        object.__setattr__(self, "direction_vector", r)
        object.__setattr__(self, "t", ts)
        object.__setattr__(self, "values", vs)

    def _pattern(self, system: Model) -> NDArray[np.float64]:
        r = self.direction_vector
        if isinstance(r, str):
            raise ValueError(
                f"`direction_vector` {r!r} is a component name: add the load to a labelled "
                "system (System.add_load) to make it a vector"
            )
        if r.shape != (system.n_dof,):
            raise ValueError(
                f"`direction_vector` must have length n_dof = {system.n_dof}, got {r.shape[0]}"
            )
        return -np.asarray(system.M @ r, dtype=np.float64)

    def _time(self) -> _core.TimeFunction:
        return _table_time(self.t, self.values, False)

    def _scalar(self, t: NDArray) -> NDArray:
        return _table_eval(t, self.t, self.values, False)


@dataclass(frozen=True, eq=False)
class Callable(Load):
    """Escape hatch: ``fn(t)`` returns the whole load vector (length ``n_dof``).

    Called from the time loop, with the GIL, once per evaluation time (the start and middle
    of every step), never per degree of freedom. Slower than the built-in loads; prefer
    those where they fit.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> load = duhamel.loads.Callable(lambda t: np.array([np.exp(-t), 0.0]))
    """

    fn: CallableT[[float], ArrayLike] = field()

    def __post_init__(self) -> None:
        if not callable(self.fn):
            raise TypeError(f"`fn` must be callable, got {type(self.fn).__name__}")

    def _validate(self, system: Model) -> None:
        return None

    def evaluate(self, system: Model, t: ArrayLike) -> NDArray[np.float64]:
        """The load vectors at times `t` (see :meth:`Load.evaluate`)."""
        ts = np.asarray(t, dtype=np.float64)
        rows = [np.asarray(self.fn(float(x)), dtype=np.float64) for x in np.atleast_1d(ts)]
        out = np.stack(rows)
        return out[0] if ts.ndim == 0 else out


@old_spellings(
    positional=("dof_x", "dof_y", "m_e", "speed", "phase"), merged={"dofs": ("dof_x", "dof_y")}
)
@dataclass(frozen=True, eq=False)
class Unbalance(Load):
    """The rotating force of an unbalance `m_e` (mass times eccentricity, kg m) on the
    shaft-centre degrees of freedom ``dofs = (x, y)``, driven by `speed` (rad/s: a number
    for a constant speed, or a law from :mod:`duhamel.speed` such as :class:`LinearRunUp`):
    ``Unbalance(dofs, *, m_e, speed, phase=0.0)``.

    With ``Theta = theta(t) + phase`` (``theta`` the rotation angle, the integral of the
    speed ``omega``) the mass sits at ``e (cos Theta, sin Theta)`` from the shaft centre, and
    the shaft carries minus ``m`` times its acceleration relative to the centre:

    ``f_x = m_e (omega^2 cos Theta + omega' sin Theta)``,
    ``f_y = m_e (omega^2 sin Theta - omega' cos Theta)``.

    At constant speed these are the harmonic loads ``m_e omega^2 sin(omega t + phase + pi/2)``
    and ``m_e omega^2 sin(omega t + phase)``. The load is evaluated in Rust; within a step
    :class:`~duhamel.Semianalytic` represents it by a parabola like any load (fourth order),
    and integrates exactly the jump of ``m_e omega'`` at the end of a run-up (and of the
    force's first two derivatives) wherever it falls.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> rotor = duhamel.System(np.eye(2), 1e4 * np.eye(2), zeta=0.02)
    >>> run_up = duhamel.loads.LinearRunUp(omega0=0.0, omega1=200.0, t1=2.0)
    >>> _ = rotor.add_load(duhamel.loads.Unbalance((0, 1), m_e=1e-4, speed=run_up))
    >>> rotor.loads[0].evaluate(rotor, 0.0)   # at rest: only the tangential omega' term
    array([ 0.  , -0.01])
    """

    dofs: tuple[Dof, Dof]
    _: KW_ONLY
    m_e: float
    speed: float | SpeedLaw
    phase: float = 0.0

    def __post_init__(self) -> None:
        dofs = self.dofs
        if is_label(dofs) or isinstance(dofs, bytes) or not isinstance(dofs, Sequence):
            raise TypeError(
                "`dofs` must be the shaft centre's two dofs (x, y), indices or labels, "
                f"got {dofs!r}"
            )
        if len(dofs) != 2:
            raise ValueError(
                f"`dofs` must be the shaft centre's two dofs (x, y), got {len(dofs)}: {dofs!r}"
            )
        object.__setattr__(self, "dofs", tuple(dofs))
        if finite_float(self.m_e, "m_e") < 0.0:
            raise ValueError(f"`m_e` must be >= 0 (mass times eccentricity), got {self.m_e!r}")
        object.__setattr__(self, "m_e", float(self.m_e))
        object.__setattr__(self, "phase", finite_float(self.phase, "phase"))
        object.__setattr__(self, "speed", as_speed_law(self.speed, "speed"))

    @property
    def dof_x(self) -> Dof:
        """Deprecated: ``dofs[0]``."""
        deprecated("Unbalance: `dof_x` is deprecated, use `dofs[0]`")
        return self.dofs[0]

    @property
    def dof_y(self) -> Dof:
        """Deprecated: ``dofs[1]``."""
        deprecated("Unbalance: `dof_y` is deprecated, use `dofs[1]`")
        return self.dofs[1]

    def _indices(self, system: Model) -> tuple[int, int]:
        dx = _index(system, self.dofs[0], "dofs[0]")
        dy = _index(system, self.dofs[1], "dofs[1]")
        if dx == dy:
            raise ValueError(f"`dofs` must be two different dofs (x, y), got {dx} twice")
        return dx, dy

    def _validate(self, system: Model) -> None:
        self._indices(system)

    def _parts(self, system: Model) -> list[tuple[NDArray[np.float64], _core.TimeFunction]]:
        law = self.speed._law()  # type: ignore[union-attr]  # a law since __post_init__
        out = []
        for dof, axis in zip(self._indices(system), ("x", "y"), strict=True):
            pattern = np.zeros(system.n_dof)
            pattern[dof] = self.m_e
            out.append((pattern, _core.TimeFunction.unbalance(law, self.phase, axis)))
        return out

    def evaluate(self, system: Model, t: ArrayLike) -> NDArray[np.float64]:
        """The load vectors at times `t` (see :meth:`Load.evaluate`), as the engine computes
        them (right-continuous at the end of a run-up)."""
        ts = np.asarray(t, dtype=np.float64)
        flat = np.ascontiguousarray(np.atleast_1d(ts).ravel())
        out = np.zeros((flat.size, system.n_dof))
        for term in self._terms(system):
            out += np.outer(term.time.values(flat), term.pattern)
        return out[0] if ts.ndim == 0 else out


def support_terms(loads: Sequence[Load], dofs: NDArray[np.int64]) -> list[tuple[NDArray, Any]]:
    """Per support-acceleration load of `loads`: its influence vector at `dofs` and its
    ground acceleration ``a_g(t)`` (what turns relative accelerations into absolute ones).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> quake = duhamel.loads.BaseAcceleration(np.ones(3), t=[0.0, 1.0], values=[0.0, 2.0])
    >>> [(r.tolist(), ag(np.array([0.5])).tolist()) for r, ag in
    ...  support_terms([quake], np.array([0, 2]))]
    [([1.0, 1.0], [1.0])]
    """
    return [
        (np.asarray(load.direction_vector)[dofs], load._scalar)
        for load in loads
        if isinstance(load, BaseAcceleration)
    ]
