"""The semi-analytic integrator's settings (the engine's modal routes)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from duhamel._engine.validate import _int_scalar, finite_float, positive_int
from duhamel.integrators.base import Integrator, newton_options

__all__ = ["Semianalytic"]

_CHOICES = {
    "scheme": ("a", "b", "c", "hermite"),
    "quadrature": ("trapezoid", "parabolic", "exact"),
    "mass_treatment": ("eliminate", "estimate"),
    "solver": ("auto", "newton", "modal-newton"),
    "coupling": ("auto", "exact", "pseudo-force"),
    "linear_parts": ("auto", "background", "pseudo-force"),
}


@dataclass(frozen=True)
class Semianalytic(Integrator):
    """The semi-analytic (Duhamel, "BEM in time") integrator of Holl, Belyaev and Irschik.

    Every modal oscillator of the linear background system is advanced with its exact
    transition and load-transfer matrices, so a linear time-invariant system is integrated
    exactly (to round-off) whatever the step, for loads that are polynomials of degree <= 2
    in time within each step. Linear couplings of the modes (non-classical damping,
    gyroscopic and cross-coupled terms) are integrated exactly too, in the first-order
    modes of the coupled system (see `coupling`). Everything else — element forces,
    time-varying mass, couplings that follow a time-varying speed — enters as a modal
    pseudo-force whose evolution over the step is approximated.

    Parameters
    ----------
    modes : int, optional
        Keep only the lowest `modes` modes (modal reduction). Default: all modes.
    scheme : {"a", "b", "c", "hermite"}
        State inside the step for evaluating pseudo-forces (the paper's eq. 20): "a" constant
        velocity ``(v0 + v1)/2``; "b" displacement linear from ``x0`` to ``x1``, velocity
        ``(x1 - x0)/dt`` — unconditionally stable, the default; "c" the parabola through
        ``x0`` (slope ``v0``) and ``x1``. "hermite": the cubic Hermite interpolant of the
        start and end states (displacement and velocity), with the parabolic quadrature —
        the **fourth-order** step (the linear part still exact; stable on the linear test
        equation whatever share of the stiffness is a pseudo-force, as far as measured: up
        to the stiffness watch's ``omega_c dt = 2``; docs/nonlinear.md, "The fourth-order
        step"). Both halves of the end state are then unknown: one mode is solved on
        scalars, more modes by Newton on all the modal coordinates (``2 n`` unknowns).
    quadrature : {"trapezoid", "parabolic", "exact"} or None
        How the pseudo-force along that state is integrated against ``A(dt - tau)``: linear
        between its start and end values; the parabola through start, middle and end; or
        the cubic through four values, exact for polynomial forces of degree <= 3 along
        schemes "a" and "b". The default (None) is "trapezoid" for schemes "a", "b", "c"
        — the most accurate there in our measurements (docs/nonlinear.md: 5x smaller errors
        on the paper's Duffing case) — and "parabolic" for "hermite", the only one it takes
        (with "trapezoid" it would be of second order).
    tol : float
        Relative tolerance of the Newton updates.
    max_iter : int
        Newton iterations per step before the run stops with a :class:`duhamel.SolverError`.
    mass_treatment : {"eliminate", "estimate"}
        Time-varying mass: divide the equation of motion by the mass law (no acceleration
        needed; the default, more accurate) or estimate the acceleration as ``(v1 - v0)/dt``.
    solver : {"auto", "newton", "modal-newton"}
        "auto" solves a single-mode step with polynomial forces of degree <= 3 in closed form
        (the cubic of the paper), and iterates otherwise; "newton" always iterates. Both
        iterate in the space of the elements' degrees of freedom when they are fewer than
        the modes and the pseudo-force is the elements' force (with no mass law, or an
        eliminated one): a step then costs about what the elements' few dofs cost, not the
        modes (docs/nonlinear.md). "modal-newton" always iterates on all the modal
        coordinates (the dense reference; it equals the element-space solution to the
        Newton tolerance).
    subdivisions : int
        Automatic step subdivision: a step whose equation does not converge within
        `max_iter` iterations is retried as two half steps, each of them in halves again if
        it fails, down to ``dt / 2**subdivisions`` (0: the run stops with a
        :class:`duhamel.SolverError` instead). Every level steps the modal oscillators
        with its own exact matrices; the substeps see the step's load (its quadratic in
        time); hysteretic elements commit at every accepted substep. The same levels take
        the steps an element at least twice as stiff as the modes it loads dominates: to
        ``omega_c dt <= 2`` of the closed state for stability (the step is unstable beyond
        ``2 sqrt(3)``; when the levels cannot, the run stops with ``reason="stiffness"``
        naming the element), and, as far as the levels go, to ``omega_c dt <= 1`` and a
        stiffness change of at most a factor e**2 per substep for accuracy
        (docs/nonlinear.md, "Stiff elements"). The coupled route (``coupling="exact"``)
        does not subdivide: it stops beyond ``omega_c dt = 0.5``. How many steps needed
        it and how deep: ``stats.subdivided_steps``, ``stats.subdivision_depth``.
    coupling : {"auto", "exact", "pseudo-force"}
        Modal couplings — non-classical damping, gyroscopic and cross-coupled
        (circulatory) terms, i.e. constant :class:`duhamel.elements.LinearCoupling`
        elements and a damping matrix that the modes do not diagonalise. "exact" integrates
        the coupled linear background exactly in its first-order (complex) modes
        (docs/coupled.md): a linear system is then exact like an uncoupled one, and with
        nonlinear elements only the element forces are pseudo-forces (scheme "b",
        "trapezoid" quadrature). "pseudo-force" treats the couplings as the paper does, as
        pseudo-forces (second order in ``dt``). "auto" (default) is "exact" where it
        applies and the first-order eigenvectors are well conditioned (condition number
        <= 1e4), "pseudo-force" otherwise (a mass law, couplings scaled by a time-varying
        speed law, another scheme or quadrature with elements, a nearly defective system).
        ``solve`` raises ValueError when "exact" cannot be honoured.
    linear_parts : {"auto", "background", "pseudo-force"}
        Where the elements' linear stiffness goes — a `Spring`'s ``k``, a `Polynomial`'s
        linear coefficient, the initial stiffness of `Bilinear` and `BoucWen`, a
        `FrictionPendulum`'s ``W / R``. "background": the modes are computed from ``K``
        plus those parts (the effective link stiffness of FNA) and only the remainder is a
        pseudo-force, so a reduced basis sees the links and a linear spring is exact;
        Rayleigh damping and a damping matrix keep their meaning, modal damping ratios
        (`zeta`) become those of these modes (FNA's convention). "pseudo-force": the whole
        element force is a pseudo-force on the modes of ``K``. "auto" (default):
        "background", except with modal damping ratios, whose meaning it keeps
        ("pseudo-force"). Also "pseudo-force" whatever is asked: a mass law that scales the
        stiffness, a basis given to ``System.use_basis`` (docs/nonlinear.md).
    static_correction : bool or None
        With `modes` below the number of dofs: enrich the modes with the static responses
        to unit forces along the elements' deformations and to the load patterns
        (load-dependent Ritz vectors, as FNA uses), mass-orthogonalised and made modal by a
        Rayleigh-Ritz solve, so every coordinate is still an exact oscillator. It gives the
        local response at stiff links and under concentrated loads that the truncated modes
        would carry (on a 120-dof chain with three stiff springs: 87 % error at the springs
        with 5 modes, 2e-5 with 5 modes + 4 vectors); the run then has more coordinates
        than `modes` (``stats.modes``). None (default): on when `modes` is given and the
        system has elements; a linear run keeps its plain modal truncation unless True.
    growth_limit : float or None
        The growth guard of nonlinear runs on passive models (passive elements, dissipative
        or gyroscopic couplings, no mass law): the run stops with ``reason="growth"`` when
        the modal energy of the response exceeds `growth_limit` times the most the initial
        state ``E0`` and the loads can give such a model, ``(sqrt(E0) + int |p| dt /
        sqrt(2))**2``: a finite explosion of an unstable step cannot pass as a result
        (docs/nonlinear.md, "Stiff elements"). Default 100 (ten times the amplitude). None
        turns it off. Models that can gain energy by themselves (a Python element, a
        journal bearing, negative damping, a mass law) are not guarded.
    error_warning : float or None
        Every run of the default step (scheme "b", "trapezoid") estimates its error
        (``sol.stats.error_estimate`` at the saved dofs, ``element_error_estimate`` at the
        elements, each relative to its peak; docs/accuracy.md) and bounds it
        (``error_bound``, ``element_error_bound``), and warns with a
        :class:`duhamel.AccuracyWarning` when the bound exceeds `error_warning`. Default 0.01 (1 %
        of the peak); None: no warning (the estimate is still made). A reduced run also
        estimates its basis's truncation (``sol.stats.truncation_estimate``,
        ``element_truncation_estimate``) and warns above the same threshold.
    rtol, atol : float or None, float
        Steps chosen by tolerance: with `rtol`, the run is repeated in steps of
        ``dt / 2**k``, ``k`` raised as the error estimate requires, until the estimate is
        within ``atol + rtol * peak`` at the saved dofs and ``rtol`` (plus `atol` over the
        peak) at every element's deformation; the saved instants stay the user's
        (``stats.substeps`` is ``2**k``). ``k`` stops at `subdivisions`: a run still above
        the tolerance there raises :class:`duhamel.SolverError` with
        ``reason="tolerance"``. The estimate is a bound (docs/accuracy.md), so the true
        error is usually several times below `rtol`. The refinement is of the whole run,
        not step by step. Only with the default step (scheme "b", "trapezoid"). Default
        None (the run at `dt`), `atol` 0.

    Examples
    --------
    >>> import duhamel
    >>> duhamel.Semianalytic()
    Semianalytic(modes=None, scheme='b', quadrature='trapezoid', tol=1e-10, max_iter=25, \
mass_treatment='eliminate', solver='auto', coupling='auto', subdivisions=4, \
linear_parts='auto', static_correction=None, growth_limit=100.0, error_warning=0.01, \
rtol=None, atol=0.0)
    >>> duhamel.Semianalytic(modes=5, quadrature="exact").quadrature
    'exact'
    >>> duhamel.Semianalytic(scheme="hermite").quadrature  # the fourth-order step
    'parabolic'
    """

    modes: int | None = None
    scheme: str = "b"
    quadrature: str | None = None
    tol: float = 1e-10
    max_iter: int = 25
    mass_treatment: str = "eliminate"
    solver: str = "auto"
    coupling: str = "auto"
    subdivisions: int = 4
    linear_parts: str = "auto"
    static_correction: bool | None = None
    growth_limit: float | None = 100.0
    error_warning: float | None = 0.01
    rtol: float | None = None
    atol: float = 0.0

    def __post_init__(self) -> None:
        if self.growth_limit is not None:
            limit = finite_float(self.growth_limit, "growth_limit")
            if not limit > 1.0:
                raise ValueError(
                    f"`growth_limit` must be a number above 1 (or None: no guard), got {limit}"
                )
            object.__setattr__(self, "growth_limit", limit)
        if self.modes is not None:
            object.__setattr__(self, "modes", positive_int(self.modes, "modes"))
        if self.error_warning is not None:
            level = finite_float(self.error_warning, "error_warning")
            if not level > 0.0:
                raise ValueError(
                    f"`error_warning` must be a positive number (or None: no warning), got {level}"
                )
            object.__setattr__(self, "error_warning", level)
        if self.quadrature is None:
            quadrature = "parabolic" if self.scheme == "hermite" else "trapezoid"
            object.__setattr__(self, "quadrature", quadrature)
        elif self.scheme == "hermite" and self.quadrature != "parabolic":
            raise ValueError(
                f"`quadrature` must be 'parabolic' (or None) with scheme='hermite' (the "
                f"fourth-order step's quadrature), got {self.quadrature!r}"
            )
        for name, allowed in _CHOICES.items():
            value = getattr(self, name)
            if value not in allowed:
                raise ValueError(f"`{name}` must be one of {allowed}, got {value!r}")
        newton_options(self.tol, self.max_iter)
        depth = _int_scalar(self.subdivisions, "subdivisions")
        if not 0 <= depth <= 30:
            raise ValueError(f"`subdivisions` must be an integer in [0, 30], got {depth}")
        object.__setattr__(self, "subdivisions", depth)
        if self.static_correction is not None:
            if not isinstance(self.static_correction, bool | np.bool_):
                raise TypeError(
                    f"`static_correction` must be True, False or None, got "
                    f"{self.static_correction!r}"
                )
            object.__setattr__(self, "static_correction", bool(self.static_correction))
        self._check_tolerance()

    def _check_tolerance(self) -> None:
        atol = finite_float(self.atol, "atol")
        if not atol >= 0.0:
            raise ValueError(f"`atol` must be a number >= 0, got {atol}")
        object.__setattr__(self, "atol", atol)
        if self.rtol is None:
            return
        rtol = finite_float(self.rtol, "rtol")
        if not 0.0 < rtol < 1.0:
            raise ValueError(f"`rtol` must be a number in (0, 1) (or None), got {rtol}")
        if self.scheme != "b" or self.quadrature != "trapezoid":
            raise ValueError(
                f"`rtol` needs the error estimate of the default step (scheme='b', "
                f"quadrature='trapezoid'), got scheme={self.scheme!r}, "
                f"quadrature={self.quadrature!r}"
            )
        object.__setattr__(self, "rtol", rtol)
