"""A run described by values: :class:`SaveAt`, what a run keeps, and :class:`RunSpec`, the run
itself (its span, its start, its loads, what it keeps and where it goes).

``duhamel.solve`` and :meth:`duhamel.Prepared.run` take the same as keywords and map them onto
these values (``save_every`` is ``SaveAt.every``, ``store`` and ``checkpoint_every`` are a
:class:`duhamel.store.Store`); code that builds runs programmatically makes the values and runs
them with :meth:`duhamel.Prepared.execute`. Both ways go through the same pipeline and give the
same numbers, bit for bit.

==================================  ============================================
keyword of ``solve`` / ``run``      the description
==================================  ============================================
``t_end``, ``t0``, ``x0``, ``v0``   ``RunSpec.t_end``, ``.t0``, ``.x0``, ``.v0``
``loads`` (``Prepared.run``)        ``RunSpec.loads``
``save_every``, ``dofs``            ``SaveAt.every``, ``SaveAt.dofs``
``t_eval``, ``dense``, ``events``   ``SaveAt.t_eval``, ``.dense``, ``.events``
``energy``                          ``SaveAt.energy``
``store``, ``checkpoint_every``     ``RunSpec.store`` (a ``duhamel.store.Store``)
``progress``                        ``RunSpec.progress``
==================================  ============================================
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.run import Progress
from duhamel._engine.validate import as_float_array, finite_float, positive_int
from duhamel.events import Event
from duhamel.loads import Load
from duhamel.store import Store

__all__ = ["RunSpec", "SaveAt"]

#: The public name of each field of a :class:`SaveAt` in the error messages, by origin.
_FIELDS = {"every": "every", "t_eval": "t_eval", "dense": "dense", "energy": "energy",
           "events": "events", "elements": "elements"}  # fmt: skip
_KEYWORDS = {**_FIELDS, "every": "save_every"}


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"`{name}` must be True or False, got {type(value).__name__}")
    return bool(value)


def _events(events: Any, name: str) -> tuple[Event, ...]:
    """`events` as a tuple of :class:`duhamel.Event` (one alone is taken as a list of one)."""
    if events is None:
        return ()
    if isinstance(events, Event):
        return (events,)
    if not isinstance(events, list | tuple):
        raise TypeError(f"`{name}` must be a list of duhamel.Event, got {type(events).__name__}")
    for k, ev in enumerate(events):
        if not isinstance(ev, Event):
            raise TypeError(f"`{name}[{k}]` must be a duhamel.Event, got {type(ev).__name__}")
    return tuple(events)


def _instants(t_eval: Any, name: str) -> NDArray[np.float64] | None:
    """`t_eval` as a 1-D increasing float array (the run's span is checked when it runs)."""
    if t_eval is None:
        return None
    times = as_float_array(t_eval, name, ndim=1)
    if times.size == 0:
        raise ValueError(
            f"`{name}` is empty: pass the instants to report (within the run), or leave it "
            "out (None) for the saved steps"
        )
    if np.any(np.diff(times) < 0):
        raise ValueError(f"`{name}` must be increasing")
    return times


@dataclass(frozen=True, slots=True, eq=False)
class SaveAt:
    """What a run keeps (diffrax's ``SaveAt`` is the model).

    Parameters
    ----------
    every : int
        Keep every `every`-th step (the last step is always kept); ``save_every`` of
        :func:`duhamel.solve`.
    dofs : sequence of int or dof labels, optional
        Degrees of freedom whose response is recovered (default: all).
    t_eval : array_like, optional
        Instants (increasing, within the run) at which the response is returned instead of
        the steps: exact on the linear routes, of the scheme's order otherwise.
    dense : bool
        Keep what ``Solution.at(t)`` needs to evaluate the response between the steps.
    events : sequence of duhamel.Event
        Zero crossings located inside their step (``Solution.events``); a terminal one ends
        the run at its instant. `t_eval`, `dense` and `events` need every step kept in
        memory (``every=1``, no store).
    energy : bool
        Accumulate the energy balance's work integrals during the run (``Solution.energy``).
    elements : bool
        Keep the elements' histories (``Solution.elements``); False leaves them out of the
        solution and of its store (the energy balance, which reads them, is then refused).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]]), zeta=0.02)
    >>> keep = duhamel.SaveAt(every=10, dofs=[1])
    >>> sol = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.01).execute(
    ...     duhamel.RunSpec(t_end=1.0, x0=[0.0, 1.0], saveat=keep))
    >>> sol.x.shape
    (11, 1)
    """

    every: int = 1
    dofs: Any = None
    t_eval: ArrayLike | None = None
    dense: bool = False
    events: Sequence[Event] = ()
    energy: bool = False
    elements: bool = True

    def __post_init__(self) -> None:
        _check(self, _FIELDS)

    @property
    def located(self) -> bool:
        """Whether the run locates events or evaluates the response inside the steps
        (`events`, `t_eval` or `dense`): every step is then kept in memory."""
        return bool(self.events) or self.t_eval is not None or self.dense


def _check(save: SaveAt, names: dict[str, str]) -> None:
    """Checks and normalises the fields of `save` in place, the messages naming `names`."""
    put = object.__setattr__
    every = save.every
    if type(every) is not int or not 1 <= every <= 2**64:
        put(save, "every", positive_int(every, names["every"], maximum=2**64))
    for key in ("dense", "energy", "elements"):
        value = getattr(save, key)
        if value is not True and value is not False:
            put(save, key, _flag(value, names[key]))
    events = save.events
    if type(events) is not tuple or events:
        put(save, "events", _events(events, names["events"]))
    if save.t_eval is not None:
        put(save, "t_eval", _instants(save.t_eval, names["t_eval"]))
    if save.energy and not save.elements:
        raise ValueError(
            "`elements`: the energy balance reads the elements' histories (their stored "
            "energy); keep them (`elements=True`) or leave `energy` out"
        )


#: What a run keeps by default: every step of every dof (shared: the value is immutable).
_KEEP_ALL = SaveAt()


@dataclass(frozen=True, slots=True, eq=False)
class RunSpec:
    """One run of a prepared model, described by values: what :meth:`duhamel.Prepared.run`
    takes as keywords (see the module's table), for :meth:`duhamel.Prepared.execute`.

    Parameters
    ----------
    t_end : float
        End time; the run takes ``floor((t_end - t0) / dt)`` steps.
    t0 : float
        Start time (default 0); loads keep their absolute time axis.
    x0, v0 : array_like, shape (n_dof,), optional
        Initial displacements and velocities (zero by default).
    loads : list of duhamel.loads loads, optional
        The loads of this run instead of the system's (None: the system's own).
    saveat : SaveAt
        What the run keeps (default: every step of every dof).
    store : duhamel.store.Store, str or os.PathLike, optional
        Where the run goes: None keeps it in memory; a store (a path means ``Store(path)``)
        streams it to a new zarr store with checkpoints (:func:`duhamel.resume`).
    progress : bool or callable, optional
        A progress bar (``True``) or a function ``(step, n_steps, t)``.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> s = duhamel.System(np.eye(1), np.array([[4.0]]))
    >>> p = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.1)
    >>> spec = duhamel.RunSpec(t_end=1.0, x0=[1.0], saveat=duhamel.SaveAt(every=5))
    >>> a = p.execute(spec)
    >>> b = p.run(t_end=1.0, x0=[1.0], save_every=5)   # the same run, as keywords
    >>> bool(np.array_equal(a.x, b.x)), a.t.tolist()
    (True, [0.0, 0.5, 1.0])
    """

    t_end: float
    t0: float = 0.0
    x0: ArrayLike | None = None
    v0: ArrayLike | None = None
    loads: Sequence[Load] | None = None
    saveat: SaveAt = field(default=_KEEP_ALL)
    store: Store | None = None
    progress: bool | Progress | None = False

    def __post_init__(self) -> None:
        put = object.__setattr__
        for key in ("t_end", "t0"):
            value = getattr(self, key)
            if type(value) is not float:
                put(self, key, finite_float(value, key))
            elif value - value != 0.0:  # inf or nan
                finite_float(value, key)
        if type(self.saveat) is not SaveAt and not isinstance(self.saveat, SaveAt):
            raise TypeError(f"`saveat` must be a duhamel.SaveAt, got {type(self.saveat).__name__}")
        if self.store is not None and not isinstance(self.store, Store):
            put(self, "store", Store(_path(self.store)))


def _path(store: Any) -> str | os.PathLike[str]:
    if not isinstance(store, str | os.PathLike):
        raise TypeError(
            f"`store` must be a path (str or os.PathLike) or a duhamel.store.Store, got "
            f"{type(store).__name__}"
        )
    return store


def from_keywords(
    *,
    t_end: Any,
    t0: Any,
    x0: Any,
    v0: Any,
    loads: Any,
    save_every: Any,
    dofs: Any,
    store: Any,
    checkpoint_every: Any,
    progress: Any,
    events: Any,
    t_eval: Any,
    dense: Any,
    energy: Any,
) -> RunSpec:
    """The :class:`RunSpec` of the keywords of ``solve`` and ``Prepared.run``, checked with
    the messages naming the keywords (``save_every``, ``checkpoint_every``)."""
    if save_every == 1 and dofs is None and t_eval is None and events is None and not (
        dense or energy
    ) and type(dense) is bool and type(energy) is bool:  # fmt: skip
        save = _KEEP_ALL  # the common case, without a new value
    else:
        save = object.__new__(SaveAt)
        put = object.__setattr__
        for key, value in (("every", save_every), ("dofs", dofs), ("t_eval", t_eval),
                           ("dense", dense), ("events", events), ("energy", energy),
                           ("elements", True)):  # fmt: skip
            put(save, key, value)
        _check(save, _KEYWORDS)
    if checkpoint_every is not None:
        every = positive_int(checkpoint_every, "checkpoint_every")
        if store is None:
            raise ValueError(
                f"`checkpoint_every` = {every} needs `store` (checkpoints are written into a "
                "streamed run's store); pass `store=` or leave `checkpoint_every` out"
            )
        store = replace(store if isinstance(store, Store) else Store(_path(store)),
                        checkpoint_every=every)  # fmt: skip
    return RunSpec(t_end, t0, x0, v0, loads, save, store, progress)
