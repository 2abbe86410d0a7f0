"""The energy balance of a run (:attr:`duhamel.Solution.energy`).

Computed after the run from the saved histories, which must hold every step
(``save_every=1``) and every dof. State functions are exact at the saved instants: kinetic
energy ``v^T M v / 2`` (and absolute ``v_abs^T M v_abs / 2``), linear strain energy
``x^T K x / 2``. The work terms are integrated by the trapezoidal rule over the steps (second
order in ``dt``): damping ``int v^T C v dt``, input ``int v^T f dt`` (relative: ``f`` the
loads, ``-M r a_g`` for the support motion; for a modal run ``int q'^T p dt``, the modal
model's own input), absolute input ``int v_g r^T M a_abs dt`` plus the other loads' work,
and each element's work ``int F . du`` over its own force-deformation path (the
trapezoid in the deformation: the loop integral of its hysteresis). The balance error
``input - (kinetic + strain + damping + hysteretic)`` thus converges to zero like ``dt^2``
(with the integrator's own error).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Energy", "energy_balance", "energy_from_run", "stored_energy"]


@dataclass(frozen=True, eq=False)
class Energy:
    """Energies over the saved instants, from the start of the run.

    Attributes
    ----------
    t : ndarray, shape (n_saved,)
    kinetic : ndarray
        Kinetic energy of the relative motion, ``v^T M v / 2``.
    kinetic_absolute : ndarray
        Kinetic energy of the absolute motion (equal to `kinetic` without support motion).
    strain : ndarray
        Recoverable strain energy: `strain_linear` plus the elements' stored part
        (`element_stored` summed).
    strain_linear : ndarray
        ``x^T K x / 2`` of the linear stiffness.
    damping : ndarray
        Energy dissipated by the damping matrix, ``int v^T C v dt``.
    elements : ndarray, shape (n_saved, n_elements)
        Work done on each element, ``int F . du`` (hysteretic dissipation plus stored part).
    element_stored : ndarray, shape (n_saved, n_elements)
        Each element's recoverable energy where defined (the energy released by unloading
        along its elastic branch: ``F^2 / 2k`` of a Bilinear, the pendulum's gravity and
        sticking energy of a FrictionPendulum, a Spring's potential); 0 for dampers and
        elements without one.
    hysteretic : ndarray
        Energy dissipated by the elements: their work less the change of their stored
        energy, summed.
    input : ndarray
        Input energy of the relative formulation, ``int v^T f dt``.
    input_absolute : ndarray
        Input energy of the absolute formulation; ``input_absolute - input`` is
        ``kinetic_absolute - kinetic`` (to the quadrature's accuracy).
    error : ndarray
        The balance ``input - (kinetic + strain + damping + hysteretic)``, the state
        functions counted from their initial values.
    """

    t: NDArray[np.float64]
    kinetic: NDArray[np.float64]
    kinetic_absolute: NDArray[np.float64]
    strain: NDArray[np.float64]
    strain_linear: NDArray[np.float64]
    damping: NDArray[np.float64]
    elements: NDArray[np.float64]
    element_stored: NDArray[np.float64]
    hysteretic: NDArray[np.float64]
    input: NDArray[np.float64]
    input_absolute: NDArray[np.float64]
    error: NDArray[np.float64]

    @property
    def relative_error(self) -> float:
        """``max |error|`` over the run divided by ``max |input|`` (0 without input)."""
        scale = float(np.abs(self.input).max()) if self.input.size else 0.0
        return float(np.abs(self.error).max()) / scale if scale > 0 else 0.0

    def plot(self, ax: Any = None) -> Any:
        """Stacked kinetic, strain, damping and hysteretic energies with the input on top;
        returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(8, 4))
        parts = [self.kinetic, self.strain, self.damping, self.hysteretic]
        names = ["kinetic", "strain", "damping", "elements (hysteretic)"]
        ax.stackplot(self.t, *parts, labels=names, alpha=0.8)
        ax.plot(self.t, self.input, "k", lw=1.0, label="input")
        ax.set_xlabel("t")
        ax.set_ylabel("energy")
        ax.legend(loc="upper left")
        ax.grid(True, alpha=0.3)
        return ax


def _cumtrapz(y: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
    out = np.zeros_like(t)
    if t.size > 1:
        out[1:] = np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))
    return out


def _quad(matrix: Any, x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``x_n^T A x_n`` per row of `x`."""
    if matrix is None:
        return np.zeros(x.shape[0])
    ax = np.asarray((matrix @ x.T).T)
    return np.einsum("ij,ij->i", x, ax)


def stored_energy(element: Any, u: NDArray[np.float64], f: NDArray[np.float64]) -> NDArray:
    """An element's recoverable energy from its local displacements `u` and forces `f`
    (shape (n_t, n_local)); zeros where the element defines none."""
    method = getattr(element, "_stored_energy", None)
    if method is None:
        return np.zeros(u.shape[0])
    u2 = np.asarray(u, dtype=np.float64).reshape(u.shape[0], -1)
    f2 = np.asarray(f, dtype=np.float64).reshape(u2.shape)
    return np.asarray(method(u2.tolist(), f2.tolist()), dtype=np.float64)


def energy_balance(sol: Any, model: Any) -> Energy:
    """The :class:`Energy` of `sol` with the physical model `model`."""
    t = np.asarray(sol.t)
    n = model.n_dof
    if sol.dofs.size != n or not np.array_equal(sol.dofs, np.arange(n)):
        raise ValueError("the energy balance needs every dof saved: solve with `dofs=None`")
    dt = sol.meta.get("dt")
    if t.size > 1 and dt is not None and not np.allclose(np.diff(t), dt, rtol=1e-9, atol=0.0):
        raise ValueError(
            "the energy balance needs every step saved (its work terms are integrated over "
            "the steps): solve with `save_every=1`"
        )
    x, v = np.asarray(sol.x), np.asarray(sol.v)
    kinetic = 0.5 * _quad(model.m, v)
    strain_linear = 0.5 * _quad(model.k, x)
    damping = _cumtrapz(_quad(model.c, v), t)
    grounds = [np.asarray(ground(t), dtype=np.float64) for _, ground in model.base]
    mr = [np.asarray(model.m @ r, dtype=np.float64).ravel() for r, _ in model.base]
    base_power = sum((-(v @ w) * ag for w, ag in zip(mr, grounds, strict=True)), np.zeros(t.size))
    if sol.modal is not None:
        power = np.einsum("ij,ij->i", sol.modal.v, sol.modal.p)
    elif model.other_loads:
        raise ValueError(
            "the energy balance of a direct integrator's run covers support motion only; "
            "this system has other loads (use duhamel.Semianalytic())"
        )
    else:
        power = base_power
    v_abs = v.copy()
    absolute_power = power - base_power
    for (r, _), w, ag in zip(model.base, mr, grounds, strict=True):
        vg = _cumtrapz(ag, t)
        v_abs += np.outer(vg, r)
        absolute_power = absolute_power + vg * (np.asarray(sol.a_absolute) @ w)
    kinetic_abs = 0.5 * _quad(model.m, v_abs)
    histories = _histories(sol, model)
    work = np.zeros((t.size, len(histories)))
    for k, history in enumerate(histories):
        f, u = np.asarray(history.force), np.asarray(history.x)
        increments = 0.5 * ((f[1:] + f[:-1]) * np.diff(u, axis=0)).sum(axis=1)
        work[1:, k] = np.cumsum(increments)
    states = (kinetic, kinetic_abs, strain_linear)
    return _balance(t, states, damping, work, _stored(histories, model), (power, absolute_power))


def _histories(sol: Any, model: Any) -> tuple[Any, ...]:
    histories = sol.elements if model.elements else ()
    if len(histories) != len(model.elements):
        raise ValueError("the run kept no element histories: the element work is not available")
    return tuple(histories)


def _stored(histories: tuple[Any, ...], model: Any) -> NDArray[np.float64]:
    """Each element's stored energy at the saved instants, shape (n_saved, n_elements)."""
    n = histories[0].x.shape[0] if histories else 0
    stored = np.zeros((n, len(histories)))
    for k, (history, (element, _)) in enumerate(zip(histories, model.elements, strict=True)):
        stored[:, k] = stored_energy(element, np.asarray(history.x), np.asarray(history.force))
    return stored


def _balance(
    t: NDArray, states: tuple[NDArray, NDArray, NDArray], damping: NDArray, work: NDArray,
    stored: NDArray, inputs: tuple[NDArray, NDArray], integrated: bool = False,
) -> Energy:  # fmt: skip
    """The :class:`Energy` of the state functions `states` (kinetic, absolute kinetic,
    linear strain), the work integrals and the inputs (integrated, or their powers to
    integrate by the trapezoidal rule)."""
    kinetic, kinetic_abs, strain_linear = states
    if stored.shape[0] != t.size:
        stored = np.zeros((t.size, work.shape[1]))
    strain = strain_linear + stored.sum(axis=1)
    hysteretic = (work - (stored - stored[:1])).sum(axis=1)
    work_in, absolute = inputs if integrated else (_cumtrapz(p, t) for p in inputs)
    error = work_in - (kinetic - kinetic[0]) - (strain - strain[0]) - damping - hysteretic
    return Energy(
        t=t,
        kinetic=kinetic,
        kinetic_absolute=kinetic_abs,
        strain=strain,
        strain_linear=strain_linear,
        damping=damping,
        elements=work,
        element_stored=stored,
        hysteretic=hysteretic,
        input=work_in,
        input_absolute=absolute,
        error=error,
    )


def energy_from_run(sol: Any, rows: NDArray[np.float64], emodel: Any) -> Energy:
    """The :class:`Energy` of a run that accumulated its work integrals in the core
    (``solve(..., energy=True)``): `rows` the core's integrals at the saved instants
    (``[damping, input, absolute - relative input, v_g per base, work per element]``, a
    stored run's followed by its kinetic and linear strain energies and ``w_b . v``),
    `emodel` the run's :class:`duhamel._engine.energy_run.EnergyModel`. The state functions
    are evaluated here from the saved modal coordinates and element histories."""
    t = np.asarray(sol.t)
    rows = np.asarray(rows)
    nb = emodel.base_loads.size
    model = emodel.structure
    n_core = 3 + nb + len(model.elements)
    width = sum(len(dofs) for _, dofs in model.elements)
    local = None
    if rows.shape[1] == n_core + 2 + nb + 2 * width and width > 0:
        # a direct run: the elements' local displacements and forces stored too
        local = (rows[:, n_core + 2 + nb : n_core + 2 + nb + width], rows[:, -width:])
        rows = rows[:, : n_core + 2 + nb]
    if rows.shape[1] == n_core + 2 + nb:  # a stored or direct run: its state functions too
        kinetic, strain_linear = rows[:, n_core].copy(), rows[:, n_core + 1].copy()
        wv = rows[:, n_core + 2 :]
        rows = rows[:, :n_core]
    else:
        q, v = np.asarray(sol.modal.q), np.asarray(sol.modal.v)
        kinetic = 0.5 * np.einsum("ij,ij->i", v, v @ emodel.mm.T)
        strain_linear = 0.5 * np.einsum("ij,ij->i", q, q @ emodel.km.T)
        wv = v @ emodel.base_w.T
    vg = rows[:, 3 : 3 + nb]
    kinetic_abs = kinetic + (vg * wv).sum(axis=1)
    kinetic_abs += 0.5 * np.einsum("ib,bc,ic->i", vg, emodel.base_rr, vg)
    work = np.ascontiguousarray(rows[:, 3 + nb :])
    if local is not None:
        stored, at = np.zeros((t.size, len(model.elements))), 0
        for k, (element, dofs) in enumerate(model.elements):
            cut = slice(at, at + len(dofs))
            stored[:, k] = stored_energy(element, local[0][:, cut], local[1][:, cut])
            at += len(dofs)
    else:
        histories = _histories(sol, model)
        if work.shape[1] != len(histories):
            raise ValueError(
                f"the core accumulated the work of {work.shape[1]} elements, the run has "
                f"{len(histories)}: the element work is not available"
            )
        stored = _stored(histories, model)
    states = (kinetic, kinetic_abs, strain_linear)
    inputs = (rows[:, 1].copy(), rows[:, 1] + rows[:, 2])
    return _balance(t, states, rows[:, 0].copy(), work, stored, inputs, integrated=True)
