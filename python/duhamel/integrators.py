"""Time integrators: small configuration objects passed to :func:`duhamel.solve`."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Semianalytic"]


@dataclass(frozen=True)
class Semianalytic:
    """The semi-analytic (Duhamel, "BEM in time") integrator of Holl, Belyaev and Irschik.

    Every modal oscillator of the linear background system is advanced with its exact
    transition and load-transfer matrices, so a linear time-invariant system is integrated
    exactly (to round-off) whatever the step, for loads that are polynomials of degree <= 2
    in time within each step.

    Parameters
    ----------
    modes : int, optional
        Keep only the lowest `modes` modes (modal reduction). Default: all modes.

    Examples
    --------
    >>> import duhamel
    >>> duhamel.Semianalytic()
    Semianalytic(modes=None)
    >>> duhamel.Semianalytic(modes=5)
    Semianalytic(modes=5)
    """

    modes: int | None = None

    def __post_init__(self) -> None:
        m = self.modes
        if m is not None and (isinstance(m, bool) or not isinstance(m, int) or m < 1):
            raise ValueError(f"`modes` must be a positive integer or None, got {m!r}")
