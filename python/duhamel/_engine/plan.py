"""Which route a modal run takes, decided once and kept as a small value.

A route is a background propagator (uncoupled oscillators, or the first-order modes of a
coupled system) with an optional pseudo-force corrector (docs/architecture.md):

* ``"uncoupled"``: no elements, classical damping, constant mass — exact;
* ``"first-order"``: constant couplings (non-classical damping, gyroscopic, circulatory)
  integrated exactly in the first-order modes, elements (if any) as pseudo-forces on them;
* ``"pseudo-force"``: the uncoupled background with everything else as a pseudo-force.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel._engine.background import background
from duhamel._engine.correction import enriched, resolved
from duhamel._engine.coupled import CONDITION_LIMIT, FirstOrderModes, first_order_modes
from duhamel._engine.relaxation import Massless, massless_coordinates
from duhamel.feedback import Feedback
from duhamel.integrators import Semianalytic
from duhamel.loads import Callable
from duhamel.system import ModalBasis, System

__all__ = ["Couplings", "Plan", "ScaledSpec", "core_elements", "mass", "modal_loads", "plan"]


class ScaledSpec(NamedTuple):
    """A coupling scaled by a speed law: ``law(t) (K x + C x')`` (modal or physical)."""

    k: NDArray[np.float64] | None
    c: NDArray[np.float64] | None
    law: _core.SpeedLaw


def core_elements(items: Any) -> list[_core.Element]:
    """The core elements a run evaluates: a model's elements (``duhamel.elements`` classes,
    defined in the core), the remainder of one whose linear part went into the background
    (its ``core`` element), couplings left out (a ``LinearCoupling`` is a coupling of the
    background or a pseudo-force of its own, never an element)."""
    out = []
    for item in items:
        core = getattr(item, "core", item)
        if isinstance(core, _core.Element):
            out.append(core)
    return out


@dataclass(frozen=True)
class Couplings:
    """Modal couplings: constant ones summed (a constant scale folded in), and those scaled
    by a time-varying speed law."""

    k: NDArray[np.float64] | None
    c: NDArray[np.float64] | None
    scaled: list[ScaledSpec]


@dataclass(frozen=True)
class Plan:
    """The route of a modal run.

    Attributes
    ----------
    route : {"uncoupled", "first-order", "pseudo-force"}
        Background and corrector (see the module docstring).
    basis : ModalBasis
        The retained modes.
    couplings : Couplings
        The modal couplings (empty on the uncoupled route).
    modes : FirstOrderModes or None
        The first-order modes of the coupled background (first-order route).
    coupling : str or None
        How couplings were integrated, for :class:`duhamel.SolveStats`: "exact",
        "pseudo-force", or None when there were none.
    elements : list
        The core elements of the corrector (a LinearCoupling is a coupling, not an element).
    linear : tuple
        Per force element, the linear part its background took over (``LinearPart`` or
        None; see ``duhamel._engine.background``): the element's force is the core's plus it.
    correction : ndarray
        The circular frequencies of the static-correction coordinates that carry nonlinear
        elements as pseudo-forces (empty without them): a run resolves them in time
        (``duhamel._engine.correction.substeps``).
    resolve : ndarray
        Those of `correction` a run resolves in time: the static-correction coordinates the
        elements' tangent can make unstable (``duhamel._engine.correction.resolved``; all of
        them on the first-order route).
    carried : ndarray or None
        The K-orthonormal vectors of the massless dofs' coordinates (`massless`).
    massless : Massless or None
        The coordinates of the massless dofs (quasi-static, or first-order where damping
        reaches them; ``duhamel._engine.relaxation.massless_coordinates``), None without.
    passive : bool
        Whether everything beyond the background only stores or dissipates energy (passive
        elements, symmetric positive semi-definite couplings, gyroscopic terms; no mass
        law): the growth guard of `Semianalytic` then watches the run (see
        :func:`passive`).
    """

    route: str
    basis: ModalBasis
    couplings: Couplings
    modes: FirstOrderModes | None
    coupling: str | None
    elements: list[Any]
    linear: tuple[Any, ...] = ()
    correction: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0), compare=False)
    carried: NDArray[np.float64] | None = field(default=None, compare=False)
    passive: bool = False
    resolve: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0), compare=False)
    massless: Massless | None = field(default=None, compare=False)


def modal_loads(
    loads: Any, system: System, phi: NDArray[np.float64] | None
) -> tuple[list[_core.Load], list[Any]]:
    """The built-in `loads` projected on the modes `phi` (``_core.Load``s; `phi` None: their
    physical patterns, for the direct integrators), and the Python load functions."""
    terms: list[_core.Load] = []
    fns = []
    for item in loads:
        if isinstance(item, Callable):
            fns.append(item.fn)
            continue
        if phi is None:
            terms.extend(item._terms(system))
            continue
        for physical, time in item._parts(system):
            pattern = np.ascontiguousarray(phi.T @ physical, dtype=np.float64)
            try:  # the core checks that the pattern is finite
                terms.append(_core.Load(pattern, time))
                continue
            except ValueError:
                if np.all(np.isfinite(pattern)):
                    raise
            _core.Load(physical, time)  # a physical pattern not finite: the core's error
            raise ValueError(
                f"the load {type(item).__name__} projects on the modes beyond the double "
                "range (a huge amplitude on tiny masses: the mass-normalised modes scale "
                "as 1/sqrt(`M`)): check its amplitude, `M` and the model's units"
            )
    return terms, fns


def _contiguous(m: NDArray[Any] | None) -> NDArray[Any] | None:
    return None if m is None else np.ascontiguousarray(m)


def _couplings(system: System, basis: ModalBasis) -> Couplings:
    k: NDArray[np.float64] | None = None
    c: NDArray[np.float64] | None = basis.c_coupling
    scaled = []
    for element in system.couplings:
        mk, mc = element.modal(basis.phi)
        factor = element.constant_factor()
        if factor is None:
            mk, mc = (None if m is None else np.ascontiguousarray(m) for m in (mk, mc))
            scaled.append(ScaledSpec(mk, mc, element.scale._law()))
            continue
        if mk is not None:
            mk = mk if factor == 1.0 else factor * mk
            k = mk if k is None else k + mk
        if mc is not None:
            mc = mc if factor == 1.0 else factor * mc
            c = mc if c is None else c + mc
    parts = [m for m in (k, c) if m is not None]
    parts += [m for spec in scaled for m in (spec.k, spec.c) if m is not None]
    finite = all(bool(np.isfinite(m).all()) for m in parts)
    if not finite:
        raise ValueError(
            "the modal couplings of the `LinearCoupling` elements (and of a non-classical `C`) "
            "overflow the double range: check their `K`, `C` and `scale` (a rotor's speed) "
            "and the model's units"
        )
    return Couplings(_contiguous(k), _contiguous(c), scaled)


def mass(system: System, integrator: Any) -> _core.Mass | None:
    """The system's mass law as the core takes it (``_core.Mass``, with the treatment of a
    `Semianalytic`), or None."""
    attached = system.mass_law
    if attached is None:
        return None
    treatment: Literal["eliminate", "estimate"] = getattr(integrator, "mass_treatment", "eliminate")
    return _core.Mass(attached.law._law(), attached.form, bool(attached.scale_stiffness), treatment)


def _check_massless_elements(system: System) -> None:
    """Refuses linear couplings acting on massless dofs on the modal route (their
    stiffness would not be condensed); force elements there get coordinates of their own
    (:func:`duhamel._engine.relaxation.massless_coordinates`)."""
    if system._condensation is None or not system.couplings:
        return
    massless = set(system.massless_dofs.tolist())
    for index, element in enumerate(system.couplings):
        mats = [m for m in (element.K, element.C) if m is not None]
        touched = {int(d) for m in mats for d in np.flatnonzero(np.abs(np.asarray(m)).sum(1))}
        hit = sorted(touched & massless)
        if hit:
            raise ValueError(
                f"`system.couplings[{index}]` (LinearCoupling) acts on the massless dofs {hit}: "
                "the modal route does not condense a coupling; add its matrices to `K`/`C`, "
                "or run the model with duhamel.Newmark()"
            )


def _warn_missing_mass(system: System, basis: ModalBasis) -> None:
    """Warns when a reduced basis carries less than 90 % of the mass in the direction of a
    support acceleration (:data:`duhamel.participation.MASS_TARGET`)."""
    from duhamel.loads import BaseAcceleration
    from duhamel.participation import MASS_TARGET, participation

    for item in system.loads:
        if isinstance(item, BaseAcceleration):
            p = participation(np.asarray(basis.phi), system.M, item.direction_vector, None)
            kept = float(p.cumulative[-1]) if p.total_mass > 0 else 1.0
            if kept < MASS_TARGET:
                warnings.warn(
                    f"the reduced basis ({basis.n_modes} coordinates) carries "
                    f"{100 * kept:.1f} % of the mass in the direction of a BaseAcceleration "
                    f"(less than {100 * MASS_TARGET:.0f} %): the response misses the rest; "
                    "keep more `modes` (see ModalBasis.participation)",
                    stacklevel=5,
                )


def plan(system: System, integrator: Semianalytic) -> Plan:
    """The route of `system` under `integrator`; raises ValueError when
    ``coupling="exact"`` cannot be honoured."""
    _check_massless_elements(system)
    bg = background(system, integrator.linear_parts)
    system = bg.system
    basis = system.modal(integrator.modes)
    correct = integrator.static_correction
    if correct is None:
        correct = integrator.modes is not None and bool(system.elements)
    correction = np.zeros(0)
    if correct:
        basis, correction = enriched(system, basis)
    if not system.elements:
        correction = np.zeros(0)  # the linear steps are exact at any dt
    resolve = resolved(system, basis, correction)
    carried = np.zeros((system.n_dof, 0))
    extra = massless_coordinates(system, basis)
    if extra is not None:  # massless dofs off their static relation: static or first-order
        basis, carried = extra.basis, extra.carried
        if system.mass_law is not None:
            raise ValueError(
                "a mass law on a model with elements or damping at massless dofs is not "
                "integrated by Semianalytic (their coordinates carry no mass); run it with "
                "duhamel.Newmark()"
            )
    if integrator.modes is not None:
        _warn_missing_mass(system, basis)
    elements = core_elements(system.elements)
    has_elements = bool(system.elements or system.couplings)
    coupled = basis.c_coupling is not None or bool(system.couplings)
    if not has_elements and basis.c_coupling is None and system.mass_law is None:
        return Plan(
            "uncoupled", basis, Couplings(None, None, []), None, None, elements, bg.linear,
            correction, carried, massless=extra,
        )  # fmt: skip
    couplings = _couplings(system, basis)
    route = "pseudo-force"
    modes: FirstOrderModes | None = None
    states = _states(system, basis)
    if states is not None:
        modes = _with_feedback(system, basis, integrator, couplings, states)
        route, resolve = "first-order", correction
    elif coupled and integrator.coupling != "pseudo-force":
        modes = _first_order(system, basis, integrator, couplings, extra)
        if modes is not None:
            route = "first-order"
            # the one-oscillator measurement behind `resolved` is of the undamped modes'
            # step: on the first-order modes every correction coordinate is resolved
            resolve = correction
    coupling = None if not coupled else ("exact" if modes is not None else "pseudo-force")
    quiet = passive(system, couplings, basis)
    return Plan(
        route, basis, couplings, modes, coupling, elements, bg.linear, correction, carried, quiet,
        resolve, extra,
    )  # fmt: skip


def _semidefinite(m: NDArray[np.float64] | None, *, symmetric: bool) -> bool:
    """Whether `m` is None, or its symmetric part positive semi-definite (and `m` itself
    symmetric when `symmetric`), to round-off."""
    if m is None:
        return True
    sym = 0.5 * (m + m.T)
    scale = float(np.abs(m).max(initial=0.0))
    if scale == 0.0:
        return True
    if symmetric and float(np.abs(m - m.T).max()) > 1e-10 * scale:
        return False
    return bool(np.linalg.eigvalsh(sym).min() >= -1e-10 * scale)


def passive(system: System, couplings: Couplings, basis: ModalBasis) -> bool:
    """Whether the pseudo-forces of `system` on the background of `basis` can only store or
    dissipate energy: a background without negative modal damping, no mass law (its change
    does work), every element passive (``Element._passive``), constant
    couplings with a symmetric positive semi-definite stiffness and a positive
    semi-definite damping (symmetric part), speed-scaled couplings without stiffness and
    with skew-symmetric (gyroscopic) damping. Then the growth guard's bound holds."""
    if system.mass_law is not None or bool((np.asarray(basis.c) < 0.0).any()):
        return False
    if any(isinstance(e, Feedback) for e in system.couplings):
        return False  # a controller supplies energy
    if not all(e._passive() for e in system.elements):
        return False
    if not _semidefinite(couplings.k, symmetric=True):
        return False
    if not _semidefinite(couplings.c, symmetric=False):
        return False
    for spec in couplings.scaled:
        if spec.k is not None and np.any(spec.k != 0.0):
            return False
        if spec.c is not None and np.abs(spec.c + spec.c.T).max(initial=0.0) > 1e-10 * np.abs(
            spec.c
        ).max(initial=0.0):
            return False
    return True


def _states(system: System, basis: ModalBasis) -> Any:
    """The system's feedback states in modal form (``coupled.States``), or None."""
    parts = [e.modal_states(basis.phi) for e in system.couplings if isinstance(e, Feedback)]
    if not parts:
        return None
    import scipy.linalg

    A = scipy.linalg.block_diag(*(a for a, _, _ in parts))
    B = np.concatenate([b for _, b, _ in parts], axis=0)
    F = np.concatenate([f for _, _, f in parts], axis=1)
    return A, B, F


def _with_feedback(
    system: System, basis: ModalBasis, integrator: Semianalytic, couplings: Couplings, states: Any
) -> FirstOrderModes:
    """The first-order modes of the closed loop (modal coordinates and feedback states):
    the only route that integrates feedback states; a ValueError says why it cannot."""
    nonlinear = bool(system.elements)
    why = None
    if integrator.coupling == "pseudo-force":
        why = "coupling='pseudo-force' cannot carry them (use coupling='auto' or 'exact')"
    elif system.mass_law is not None:
        why = "a mass law is not supported with them"
    elif couplings.scaled:
        why = (
            "couplings scaled by a time-varying speed law (a run-up) are not supported with "
            "them on this route"
        )
    elif nonlinear and (integrator.scheme, integrator.quadrature) != ("b", "trapezoid"):
        why = "nonlinear elements need scheme='b' and quadrature='trapezoid' with them"
    if why is not None:
        raise ValueError(
            f"the system has feedback states (duhamel.feedback.Feedback: controllers), which "
            f"only the exact first-order route integrates: {why}"
        )
    try:
        modes = first_order_modes(basis.omega2, basis.c, couplings.k, couplings.c, states)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ValueError(
            f"the first-order modes of the system with its feedback states cannot be computed "
            f"({type(exc).__name__}: {exc})"
        ) from None
    if not modes.condition <= CONDITION_LIMIT:
        raise ValueError(
            f"the system with its feedback states (controllers) is (nearly) defective: its "
            f"first-order eigenvector matrix has condition number {modes.condition:.3g} > "
            f"{CONDITION_LIMIT:g} (its modes would lose digits); a closed loop with a "
            "repeated eigenvalue (a rigid-body mode the feedback does not hold) cannot be "
            "integrated on its modes"
        )
    return modes


def _first_order(
    system: System,
    basis: ModalBasis,
    integrator: Semianalytic,
    couplings: Couplings,
    extra: Massless | None = None,
) -> FirstOrderModes | None:
    """The first-order modes for the exact coupled route, or None for the pseudo-force
    route."""
    nonlinear = bool(system.elements)
    why = None
    if extra is not None:
        why = (
            "is not taken with coordinates of massless dofs (static or first-order, without "
            "mass): their couplings with the modes enter as pseudo-forces"
        )
    elif system.mass_law is not None or couplings.scaled:
        why = (
            "needs constant couplings and mass: no mass law, no coupling scaled by a "
            "time-varying speed law"
        )
    elif nonlinear and (integrator.scheme, integrator.quadrature) != ("b", "trapezoid"):
        why = (
            "with nonlinear elements needs scheme='b' and quadrature='trapezoid' (the element "
            "forces on the exact coupled background)"
        )
    if why is not None:
        if integrator.coupling == "exact":
            raise ValueError(
                f"`coupling`='exact' {why} (those cases enter as pseudo-forces; use "
                "coupling='auto' or 'pseudo-force')"
            )
        return None
    modes: FirstOrderModes | None
    try:
        modes = first_order_modes(basis.omega2, basis.c, couplings.k, couplings.c)
    except (np.linalg.LinAlgError, ValueError) as exc:
        # LAPACK cannot take the coupled matrix (entries near the double range)
        if integrator.coupling == "exact":
            raise ValueError(
                f"`coupling`='exact': the first-order modes of the coupled system cannot be "
                f"computed ({type(exc).__name__}: {exc}); its couplings are beyond what double "
                "precision can analyse (check the couplings' and the speed's values)"
            ) from None
        return None
    if not np.isfinite(modes.condition):
        modes = None
    if modes is None or modes.condition > CONDITION_LIMIT:
        if integrator.coupling == "exact":
            raise ValueError(
                f"`coupling`='exact': the coupled system is (nearly) defective, its first-order "
                f"eigenvector matrix has condition number "
                f"{np.inf if modes is None else modes.condition:.3g} > "
                f"{CONDITION_LIMIT:g}, so its modes would lose digits (about condition^2 * "
                f"1e-17 of the response); use coupling='pseudo-force'"
            )
        return None
    return modes
