"""The result of :func:`duhamel.solve`."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.results.forces import real_array
from duhamel.results.outputs import StructuralOutputs
from duhamel.results.stats import SolveStats, summary
from duhamel.results.structural import ElementHistory, drifts

__all__ = ["ModalHistory", "Solution", "SolveStats"]


class ModalHistory:
    """Modal coordinates of the response (mass-normalised modes).

    The time loop stores the modal coordinates and velocities; the modal accelerations follow
    exactly from the modal equations, ``a = p(t) - c v - omega^2 q - r``, with ``r`` the
    pseudo-force, and are computed on first access. A coupled linear run (integrated exactly
    in its first-order modes, see :class:`duhamel.Semianalytic`'s ``coupling``) stores the
    first-order coordinates instead, and ``q``, ``v`` are rebuilt from them on first access.

    Attributes
    ----------
    q, v : ndarray, shape (n_saved, n_modes)
        Modal coordinates and velocities.
    omega : ndarray, shape (n_modes,)
        Natural frequencies of the retained modes (rad/s).
    c : ndarray, shape (n_modes,)
        Modal damping ``2 zeta omega`` per unit modal mass.
    p : ndarray, shape (n_saved, n_modes)
        Modal load at the saved instants (the value just after each instant); computed on
        first access.
    pseudo_force : ndarray, shape (n_saved, n_modes)
        Everything outside the uncoupled background, as a modal force: element forces,
        couplings (``-(K_c q + C_c v)``), mass change; zeros for an uncoupled linear run.
    a : ndarray, shape (n_saved, n_modes)
        Modal accelerations; computed on first access.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(2), np.diag([1.0, 4.0]))
    >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.5, x0=[1.0, 0.0])
    >>> sol.modal.q.shape, sol.modal.a.shape
    ((3, 2), (3, 2))
    """

    def __init__(
        self,
        q: NDArray[np.float64] | None,
        v: NDArray[np.float64] | None,
        omega: NDArray[np.float64],
        c: NDArray[np.float64],
        load_values: NDArray[np.float64],
        patterns: NDArray[np.float64],
        forcing: NDArray[np.float64] | None = None,
        pseudo: NDArray[np.float64] | None = None,
        *,
        first_order: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
        coupling: tuple[NDArray[np.float64] | None, NDArray[np.float64] | None] | None = None,
    ) -> None:
        if (q is None or v is None) and first_order is None:
            raise ValueError("`q` and `v`, or `first_order`, must be given")
        if q is not None:
            self.__dict__["q"] = q
        if v is not None:
            self.__dict__["v"] = v
        self.omega = omega
        self.c = c
        self.load_values = load_values
        self.patterns = patterns
        self.forcing = forcing
        self.pseudo = pseudo
        self._first_order = first_order
        self._coupling = coupling

    def __repr__(self) -> str:
        return f"ModalHistory(n_saved={self.load_values.shape[0]}, n_modes={self.omega.size})"

    @cached_property
    def _qv(self) -> NDArray[np.float64]:
        assert self._first_order is not None
        z, back = self._first_order
        return z @ back

    @cached_property
    def q(self) -> NDArray[np.float64]:
        """Modal coordinates."""
        return self._qv[:, : self.omega.size]

    @cached_property
    def v(self) -> NDArray[np.float64]:
        """Modal velocities."""
        return self._qv[:, self.omega.size :]

    @cached_property
    def p(self) -> NDArray[np.float64]:
        """Modal external load at the saved instants."""
        p = self.load_values @ self.patterns.T
        return p if self.forcing is None else p + self.forcing

    @cached_property
    def pseudo_force(self) -> NDArray[np.float64]:
        """Modal pseudo-force (elements, couplings, mass change) at the saved states."""
        out = np.zeros_like(self.q) if self.pseudo is None else self.pseudo.copy()
        if self._coupling is not None:
            kc, cc = self._coupling
            if kc is not None:
                out -= self.q @ kc.T
            if cc is not None:
                out -= self.v @ cc.T
        return out

    @cached_property
    def a(self) -> NDArray[np.float64]:
        """Modal accelerations from the modal equations of motion."""
        return self.p + self.pseudo_force - self.c * self.v - self.omega**2 * self.q


class Solution(StructuralOutputs):
    """Response history of a structural model.

    Attributes
    ----------
    t : ndarray, shape (n_saved,)
        Saved times.
    x, v, a : ndarray, shape (n_saved, n_out)
        Displacements, velocities and accelerations of the output degrees of freedom
        (all, or those passed as ``dofs``). A coupled linear run (first-order modes) computes
        ``a`` from its history on first access; the others compute it with ``x`` and ``v``.
    dofs : ndarray of int, shape (n_out,)
        Which degrees of freedom the columns of `x`, `v`, `a` are.
    modal : ModalHistory or None
        The modal history the physical response was recovered from (semi-analytic
        integrator); None for the direct integrators, which step the physical coordinates.
    stats : SolveStats
        Steps and timings.
    meta : dict
        The step and the integrator.
    elements : tuple of ElementHistory
        Per force element of the system (couplings left out), in the order they were
        added: its local displacements, velocities and restoring force along the run
        (hysteresis loops: ``sol.elements[k].plot()``). Empty for the direct integrators.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.eye(1))
    >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0])
    >>> sol.x.shape, sol.t[-1]
    ((11, 1), np.float64(1.0))
    """

    def __init__(
        self,
        t: NDArray[np.float64],
        x: NDArray[np.float64],
        v: NDArray[np.float64],
        a: NDArray[np.float64] | Callable[[], NDArray[np.float64]],
        dofs: NDArray[np.int64],
        modal: ModalHistory | None,
        stats: SolveStats,
        meta: dict[str, Any] | None = None,
        *,
        elements: tuple[ElementHistory, ...] | Callable[[], tuple[ElementHistory, ...]] = (),
        base: Sequence[tuple[NDArray[np.float64], Callable[[Any], Any]]] = (),
        structure: Any = None,
    ) -> None:
        if callable(elements):
            self._elements_source: Callable[[], tuple[ElementHistory, ...]] | None = elements
        else:
            self._elements_source = None
            self.__dict__["elements"] = elements
        self._base = list(base)
        # The physical model (base shear, energy): a StructureModel or a function making it.
        self._structure_source = structure
        self.t = t
        self.x = x
        self.v = v
        if callable(a):
            self._a_source: Callable[[], NDArray[np.float64]] | None = a
        else:
            self._a_source = None
            self.__dict__["a"] = a
        self.dofs = dofs
        self.modal = modal
        self.stats = stats
        self.meta = {} if meta is None else meta
        #: The located events (``solve(..., events=)``), in time order.
        self.events: list[Any] = []
        self._dense: Any = None  # the interpolant kept by a run with dense=True
        self._exact: Any = None  # a linear route's fractional steps (dense runs)
        # (the core's energy integrals, the run's EnergyModel): solve(..., energy=True)
        self._energy_run: Any = None

    @cached_property
    def a(self) -> NDArray[np.float64]:
        """Accelerations of the output degrees of freedom."""
        assert self._a_source is not None
        return self._a_source()

    @cached_property
    def elements(self) -> tuple[ElementHistory, ...]:
        """Per force element, its history (see the class docstring); made on first access."""
        assert self._elements_source is not None
        return self._elements_source()

    def __getstate__(self) -> dict[str, Any]:
        # What is made on first access is made now: a pickled Solution holds no function.
        state = dict(self.__dict__)
        for name, source in (("a", "_a_source"), ("elements", "_elements_source")):
            if state.get(source) is not None:
                state[name] = getattr(self, name)
                state[source] = None
        if callable(state.get("_structure_source")):
            try:
                state["_structure_source"] = self._structure()
            except ValueError:  # a model without one (time-varying mass): none kept
                state["_structure_source"] = None
        state["_dense"] = state["_exact"] = None  # they hold the core's model
        return state

    def at(self, t: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Displacements and velocities of the output dofs at any instants of the run.

        Exact on the linear routes (one fractional step of the core from the saved state),
        a cubic Hermite interpolant of the scheme's order otherwise (docs/events.md). Needs
        a run with ``dense=True``.

        Parameters
        ----------
        t : float or array_like
            Instants within the run.

        Returns
        -------
        x, v : ndarray, shape (n_out,) or (len(t), n_out)

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> s = duhamel.System(np.eye(1), 4.0 * np.eye(1))
        >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0],
        ...                     dense=True)
        >>> x, v = sol.at(0.123)
        >>> bool(abs(x[0] - np.cos(0.246)) < 1e-14)
        True
        """
        if self._dense is None:
            raise ValueError(
                "`Solution.at` needs what the run kept for it: run with dense=True (and "
                "save_every=1)"
            )
        times = real_array(t, "t")  # a string is refused, not converted
        flat = np.atleast_1d(times).ravel()
        lo, hi = float(self._dense.t[0]), self._dense.end
        if flat.size and not (np.all(np.isfinite(flat)) and flat.min() >= lo and flat.max() <= hi):
            raise ValueError(f"`t` must lie within the run, [{lo:g}, {hi:g}]")
        x, v, _ = self._dense.at(flat)
        if times.ndim == 0:
            return x[0], v[0]
        return x, v

    @property
    def a_absolute(self) -> NDArray[np.float64]:
        """Absolute accelerations of the output dofs: the relative ones (:attr:`a`) plus
        the support accelerations of the system's :class:`duhamel.loads.BaseAcceleration`
        loads, ``a + sum r a_g(t)``; equal to :attr:`a` without support excitation. Like
        :attr:`a`, the value just after each saved time (a record that ends at a saved time
        contributes 0 there).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> t = np.linspace(0.0, 2.0, 201)  # the record outlasts the run
        >>> sys = duhamel.System(np.eye(1), 100.0 * np.eye(1), zeta=0.05)
        >>> quake = duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=np.sin(5 * t))
        >>> sys = sys.add_load(quake)
        >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
        >>> bool(np.allclose(sol.a_absolute[:, 0], sol.a[:, 0] + np.sin(5 * sol.t)))
        True
        """
        out = np.array(self.a, copy=True)
        for r, ground in self._base:
            out += np.outer(np.asarray(ground(self.t), dtype=np.float64), r)
        return out

    def drifts(
        self, floors: Sequence[Any], heights: Sequence[float] | float | None = None
    ) -> NDArray[np.float64]:
        """Inter-storey drifts: ``x[floors[k]] - x[floors[k-1]]``, the first storey's
        against the support (relative displacements are relative to it).

        Parameters
        ----------
        floors : sequence of int or of sequences of int
            The floors' (horizontal) dofs, bottom to top; they must be among the saved
            `dofs`. A floor given as several dofs (one per column line, the same number on
            every floor) gives the drift of largest magnitude over its column lines.
        heights : float or sequence of float, optional
            Storey heights: drift ratios instead of drifts.

        Returns
        -------
        ndarray, shape (n_t, len(floors))

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> k = 100.0 * (2 * np.eye(3) - np.eye(3, k=1) - np.eye(3, k=-1))
        >>> k[2, 2] = 100.0
        >>> sol = duhamel.solve(duhamel.System(np.eye(3), k), duhamel.Semianalytic(),
        ...                     t_end=1.0, dt=0.01, x0=[0.1, 0.2, 0.3])
        >>> d = sol.drifts([0, 1, 2], heights=3.0)
        >>> bool(np.allclose(d[0], [0.1 / 3, 0.1 / 3, 0.1 / 3]))
        True
        """
        return drifts(self.x, self.dofs, floors, heights)

    def summary(self) -> str:
        """A few lines on the run: integrator, steps, cost, peak response, the estimated
        error and its bound (``stats.error_estimate``, ``stats.error_bound``,
        docs/accuracy.md).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> system = duhamel.System(np.eye(1), np.eye(1))
        >>> system.add(duhamel.elements.Cubic(0, k3=4.0))
        System(n_dof=1, damping='none', loads=0, elements=1)
        >>> sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0])
        >>> print(sol.summary().splitlines()[-3])  # doctest: +ELLIPSIS
        estimated error: ...e-0... of the peak at the saved dofs
        """
        return summary(self)

    def __repr__(self) -> str:
        return (
            f"Solution(n_saved={self.t.size}, dofs={self.dofs.size}, modes={self.stats.modes}, "
            f"t=[{self.t[0] if self.t.size else 0.0:g}, {self.t[-1] if self.t.size else 0.0:g}])"
        )

    def to_xarray(self, labels: Sequence[str] | None = None) -> Any:
        """The history as an ``xarray.Dataset``: variables ``x``, ``v``, ``a`` with dims
        ``(time, dof)``, coordinates ``time`` (s), ``dof`` (the model's dof indices) and, with
        `labels` (one name per dof of the model; default the model's own,
        :meth:`duhamel.System.label_dofs`, e.g. a rotor's ``x_0``, ``theta_y_3``), ``label``;
        attributes ``integrator``, ``dt``, ``t0``, ``steps``. Writes to netCDF or zarr with
        xarray's ``to_netcdf``/``to_zarr``. Needs xarray (``pip install 'duhamel[xarray]'``).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> sys = duhamel.System(np.eye(2), np.diag([1.0, 4.0]))
        >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0, 0.0])
        >>> ds = sol.to_xarray(labels=["base", "roof"])
        >>> dict(ds.sizes), ds["label"].values.tolist()
        ({'time': 11, 'dof': 2}, ['base', 'roof'])
        """
        from duhamel.results.labelled import to_xarray

        return to_xarray(self, labels)

    def to_dataframe(self, quantity: str = "x", labels: Sequence[str] | None = None) -> Any:
        """One quantity (``'x'``, ``'v'`` or ``'a'``) as a ``pandas.DataFrame`` indexed by
        time, one column per saved dof (named by `labels`, or by the model's own labels).
        Needs pandas.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> sys = duhamel.System(np.eye(1), np.eye(1))
        >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.5, x0=[1.0])
        >>> sol.to_dataframe().shape
        (3, 1)
        """
        from duhamel.results.labelled import to_dataframe

        return to_dataframe(self, quantity, labels)

    def plot(self, dofs: Any = None, quantity: str = "x", ax: Any = None) -> Any:
        """Plot the history of some output degrees of freedom with matplotlib.

        Parameters
        ----------
        dofs : sequence of int, optional
            Degrees of freedom (model numbering) to draw; default: up to the first four
            output dofs.
        quantity : {"x", "v", "a"}
            Displacement, velocity or acceleration.
        ax : matplotlib Axes, optional
            Where to draw; a new figure otherwise.

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> sys = duhamel.System(np.eye(1), np.eye(1))
        >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=6.0, dt=0.1, x0=[1.0])
        >>> ax = sol.plot()
        """
        try:
            import matplotlib.pyplot as plt
        except ImportError as exc:  # pragma: no cover - depends on the install
            raise ImportError("plotting needs matplotlib: pip install 'duhamel[plot]'") from exc
        if not isinstance(quantity, str) or quantity not in ("x", "v", "a"):
            raise ValueError(f"`quantity` must be 'x', 'v' or 'a', got {quantity!r}")
        data = getattr(self, quantity)
        wanted = list(self.dofs[:4]) if dofs is None else list(np.atleast_1d(dofs))
        cols = []
        for d in wanted:
            hits = np.flatnonzero(self.dofs == d)
            if hits.size == 0:
                raise ValueError(
                    f"`dofs`: dof {d} is not among the saved dofs {self.dofs.tolist()}"
                )
            cols.append(int(hits[0]))
        if ax is None:
            _, ax = plt.subplots(figsize=(8, 4))
        label = {"x": "displacement", "v": "velocity", "a": "acceleration"}[quantity]
        for d, c in zip(wanted, cols, strict=True):
            ax.plot(self.t, data[:, c], label=f"dof {d}")
        ax.set_xlabel("t")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend()
        return ax
