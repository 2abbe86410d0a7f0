"""The statistics of a run (:class:`SolveStats`) and its one-page summary."""

from __future__ import annotations

from dataclasses import MISSING, dataclass, fields
from typing import Any

__all__ = ["SolveStats", "summary"]


@dataclass(frozen=True)
class SolveStats:
    """Cost of a run.

    Attributes
    ----------
    steps : int
        Time steps taken.
    wall_time : float
        Seconds spent in the time loop (Rust, GIL released).
    total_time : float
        Seconds for the whole call, modal analysis and back-transformation included.
    modes : int
        Modal coordinates integrated (0 for the direct integrators, which step the physical
        coordinates).
    newton_iterations : int
        Newton iterations over the run (nonlinear problems).
    closed_form_steps : int
        Steps solved by the closed-form cubic (single-mode polynomial problems).
    factorizations : int
        Direct integrators: LU factorisations of the iteration (effective stiffness)
        matrix over the run; 1 for a linear problem with constant mass (the mass matrix,
        factorised once for the initial acceleration, is not counted). Semi-analytic
        integrator: factorisations of the kept (modified Newton) iteration matrix of
        elements on the exact coupled background; 0 on the other routes.
    subdivided_steps : int
        Semi-analytic integrator: steps whose equation did not converge and that were
        retried in halves (``Semianalytic(subdivisions=...)``); a failed run's ``partial``
        counts them too (and its Newton iterations), the failing step included.
    subdivision_depth : int
        The deepest of those subdivisions: substeps of ``dt / 2**subdivision_depth``.
    coupling : str or None
        Semi-analytic integrator: how modal couplings (non-classical damping, gyroscopic
        and cross-coupled terms) were integrated: "exact" (the first-order modes of the
        coupled background; element forces, if any, as pseudo-forces on it), or
        "pseudo-force"; None when there were none (or for a direct integrator).
    eigenvector_condition : float or None
        For ``coupling == "exact"``: the 1-norm condition number ``kappa`` of the
        first-order eigenvector matrix (a few for well-separated modes; the round-off of the
        run grows like ``kappa^2`` times the unit round-off near a defective system, which
        is why ``kappa`` above ``duhamel._engine.coupled.CONDITION_LIMIT`` = 1e4 is refused).
    loop_time : float
        Seconds in the core's time loop alone, measured in Rust around it (``wall_time``
        also counts taking the run's inputs into Rust and its history out); ``total_time``
        minus ``loop_time`` is what the call cost beyond the loop.
    substeps : int
        Semi-analytic integrator: internal steps per step of ``dt`` (1 but for a reduced
        basis with static correction under nonlinear elements, whose correction coordinates
        are resolved in time, ``omega dt <= 0.5``: see docs/nonlinear.md);
        ``subdivided_steps`` and ``newton_iterations`` then count internal steps.
    error_estimate : float or None
        Semi-analytic integrator: the estimated error of the saved displacements, as a
        fraction of their peak (the pseudo-force quadrature's local errors carried over the
        run by each mode's linearised dynamics, docs/accuracy.md: within a factor 3 of the
        true error in most runs, not a bound); 0 for a linear uncoupled run (exact); None
        where it is not estimated (another scheme or quadrature, the coupled route, a
        direct integrator).
    element_error_estimate : tuple of float
        The same per element (its deformation, relative to its peak deformation).
    error_bound : float or None
        Semi-analytic integrator: a bound of the same error (the local errors added in
        magnitude rather than carried with their signs; in the family of docs/accuracy.md
        never below the true error, up to several hundred times above it on friction). The
        warning above ``Semianalytic(error_warning=...)`` (:class:`duhamel.AccuracyWarning`)
        and the steps of ``Semianalytic(rtol=...)`` go by it; None where
        ``error_estimate`` is None.
    element_error_bound : tuple of float
        The same per element.
    truncation_estimate : float or None
        Semi-analytic integrator with a reduced basis (``modes=n``): the estimated error of
        the saved displacements that the modes left out cause (relative to their peak;
        with ``static_correction``, the dynamic part the correction does not represent;
        docs/accuracy.md); 0 when nothing is left out; None where it is not estimated.
        Above ``error_warning`` the run warns (:class:`duhamel.AccuracyWarning`).
    element_truncation_estimate : tuple of float
        The same per element.
    """

    steps: int
    wall_time: float
    total_time: float
    modes: int
    newton_iterations: int = 0
    closed_form_steps: int = 0
    factorizations: int = 0
    subdivided_steps: int = 0
    subdivision_depth: int = 0
    coupling: str | None = None
    eigenvector_condition: float | None = None
    loop_time: float = 0.0
    substeps: int = 1
    error_estimate: float | None = None
    element_error_estimate: tuple[float, ...] = ()
    error_bound: float | None = None
    element_error_bound: tuple[float, ...] = ()
    truncation_estimate: float | None = None
    element_truncation_estimate: tuple[float, ...] = ()

    @classmethod
    def _of(cls, **values: Any) -> SolveStats:
        """``SolveStats(**values)`` made without the frozen dataclass's ``__init__`` (a
        per-field ``object.__setattr__``: a few microseconds of every run's fixed cost): the
        fields' defaults, then `values` (which must name every field without a default)."""
        stats = object.__new__(cls)
        stats.__dict__.update(_DEFAULTS, **values)
        return stats

    @property
    def mode_steps_per_second(self) -> float:
        """Throughput of the time loop: ``steps * modes / wall_time``."""
        return self.steps * self.modes / self.wall_time if self.wall_time > 0 else float("inf")


#: The defaults of :class:`SolveStats`' fields (:meth:`SolveStats._of`).
_DEFAULTS = {f.name: f.default for f in fields(SolveStats) if f.default is not MISSING}


def _fraction(value: float | None) -> str:
    return "not estimated" if value is None else f"{value:.2e} of the peak"


def summary(sol: Any) -> str:
    """The text of :meth:`duhamel.Solution.summary`."""
    st = sol.stats
    integrator = sol.meta.get("integrator")
    name = type(integrator).__name__ if integrator is not None else "?"
    dt = sol.meta.get("dt")
    lines = [
        f"{name}: {st.steps} steps of dt = {dt:g}, {st.modes} modal coordinates"
        if dt is not None
        else f"{name}: {st.steps} steps, {st.modes} modal coordinates",
        f"time: {st.total_time:.3g} s ({st.loop_time:.3g} s in the time loop); "
        f"{st.newton_iterations} Newton iterations, {st.subdivided_steps} steps subdivided "
        f"(depth {st.subdivision_depth})",
    ]
    if sol.x.size:
        lines.append(f"peak displacement: {float(abs(sol.x).max()):.4g} at the saved dofs")
    if st.error_estimate is None and name != "Semianalytic":
        lines.append("estimated error: not estimated (direct integrator)")
    else:
        where = "at the saved dofs"
        lines.append(f"estimated error: {_fraction(st.error_estimate)} {where}")
        if st.error_bound is not None:
            lines.append(f"error bound: {_fraction(st.error_bound)} {where}")
    worst = max(st.element_error_estimate, default=None)
    lines.append(
        "estimated error at the elements: "
        + ("none" if worst is None else f"{worst:.2e} of the peak deformation (worst)")
    )
    if st.truncation_estimate is not None:
        worst = max(st.element_truncation_estimate, default=0.0)
        lines.append(
            f"estimated basis truncation error: {_fraction(st.truncation_estimate)} at the "
            f"saved dofs, {worst:.2e} of the peak deformation at the elements (worst)"
        )
    return "\n".join(lines)
