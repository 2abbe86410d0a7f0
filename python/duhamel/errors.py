"""Exceptions raised by duhamel."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from duhamel.results.solution import Solution


class DuhamelError(Exception):
    """Base class of the errors duhamel raises besides ``ValueError``/``TypeError``."""


class DampingWarning(UserWarning):
    """A damping ratio above 1 (100 % of critical damping), which is often a percentage
    taken for a fraction (``zeta=5`` for 5 %). Heavy damping is allowed; silence the warning
    where it is meant with ``warnings.simplefilter("ignore", duhamel.DampingWarning)``."""


class MatchWarning(UserWarning):
    """Spectral matching (:func:`duhamel.records.match`) stopped at its iteration limit
    before the spectrum was within the tolerance of the target; the record returned is the
    last iterate, and its ``metadata['match']`` gives the misfit reached."""


class AccuracyWarning(UserWarning):
    """A semi-analytic run whose error bound (``sol.stats.error_bound`` at the saved dofs,
    ``sol.stats.element_error_bound`` at the elements, relative to their peaks; the message
    also gives the estimate, ``error_estimate``) exceeds the integrator's ``error_warning``
    (default 1 %): the step is too long for the response's nonlinearity. Reduce ``dt``
    (the error falls like ``dt**2``); see docs/accuracy.md for how the estimate is made
    and when it is reliable. A reduced run (``modes=n``) also warns when the error its
    basis's truncation is estimated to cause (``sol.stats.truncation_estimate``,
    ``element_truncation_estimate``) exceeds the same threshold: keep more modes (the
    message says so)."""


class InternalError(DuhamelError, RuntimeError):
    """A bug in duhamel: please report it, with the input that raised it.

    The native core failed an internal check (a Rust panic). The run is abandoned, the
    process and the interpreter are unharmed, and the message says what failed and where.
    """


class SolverError(DuhamelError, RuntimeError):
    """A simulation stopped before ``t_end``.

    Attributes
    ----------
    time : float
        The time at which the run failed.
    reason : str
        ``"nonfinite"`` (the state overflowed or became NaN: a diverging response),
        ``"convergence"`` (the implicit step equation did not converge), ``"domain"`` (an
        element reached a state it is not defined at: a journal at its bearing's wall),
        ``"stiffness"`` (an element's tangent stiffness puts the semi-analytic step beyond its
        stability limit even in ``2**subdivisions`` substeps; the message names the element
        by its index and dofs, the limit and the step that would do, see docs/nonlinear.md),
        ``"growth"`` (the response's energy outgrew by ``growth_limit`` times what the
        initial state and the loads can give a passive model: an unstable step, or a model
        that gains energy by itself), ``"tolerance"`` (``Semianalytic(rtol=...)``: the error
        estimate stays above the tolerance in steps of ``dt / 2**subdivisions``) or
        ``"callback"`` (a Python load or element function
        failed).
    step : int or None
        The step that could not be completed (steps count from 1: step ``n`` ends at
        ``t0 + n dt``), as the engine reports it.
    partial : Solution
        Everything computed up to the last good saved instant.
    """

    def __init__(
        self,
        message: str,
        *,
        time: float,
        reason: str,
        partial: Solution,
        step: int | None = None,
    ) -> None:
        super().__init__(message)
        self.time = time
        self.reason = reason
        self.step = step
        self.partial = partial
