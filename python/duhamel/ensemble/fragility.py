"""Lognormal collapse fragility from collapse intensities (:func:`fit_fragility`,
:class:`Fragility`): median and dispersion by maximum likelihood or the method of moments,
FEMA P695's collapse margin ratio.

``P(collapse | IM = x) = Phi(ln(x / median) / beta)``. From the collapse intensities
``x_1..x_n`` of an IDA (Baker 2015, "Efficient analytical fragility function fitting using
dynamic structural analysis", Earthquake Spectra 31(1), 579-599, eqs. 2-3 and 11):

- ``'mle'``: maximum likelihood, ``ln median = mean(ln x_i)``,
  ``beta^2 = sum (ln x_i - ln median)^2 / n`` (what ``scipy.stats.lognorm.fit(x, floc=0)``
  gives); records that did not collapse up to the largest intensity run (a truncated IDA)
  enter the likelihood as right-censored, ``P(X > x_max) = 1 - Phi(ln(x_max/median)/beta)``
  (Baker's eq. 11), and the two parameters are found numerically;
- ``'moments'``: the method of moments on the logarithms, the same median and the sample
  standard deviation ``beta^2 = sum (ln x_i - ln median)^2 / (n - 1)`` (Baker's eq. 3);
  it needs every record to have collapsed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, positive_float

__all__ = ["Fragility", "fit_fragility"]


@dataclass(frozen=True, eq=False)
class Fragility:
    """A lognormal collapse fragility ``P(collapse | IM = x) = Phi(ln(x / median) / beta)``
    fitted by :func:`fit_fragility` (or :meth:`duhamel.ensemble.IDA.fragility`).

    Attributes
    ----------
    median, beta : float
        The median collapse intensity and the lognormal dispersion.
    method : {'mle', 'moments'}
        How they were fitted.
    collapse_intensities : ndarray
        The data: each record's collapse intensity, ``inf`` for a record that did not
        collapse up to `censored_at`.
    censored_at : float or None
        The largest intensity run (the records beyond it are right-censored).
    mce : float or None
        The MCE intensity ``S_MT`` (FEMA P695), in the units of the intensities.
    """

    median: float
    beta: float
    method: str
    collapse_intensities: NDArray[np.float64]
    censored_at: float | None = None
    mce: float | None = None

    @property
    def cmr(self) -> float:
        """FEMA P695's collapse margin ratio ``CMR = S_CT / S_MT``: the fitted median
        collapse intensity over the MCE intensity (ValueError without `mce`). FEMA P695
        (sec. 6.3) reads ``S_CT`` as the intensity at which half the records have collapsed;
        for the fitted lognormal that is its median. The spectral-shape factor (ACMR) is not
        applied."""
        if self.mce is None:
            raise ValueError(
                "`mce` was not given: the collapse margin ratio needs the MCE intensity S_MT"
            )
        return self.median / self.mce

    def probability(self, intensity: ArrayLike) -> NDArray[np.float64]:
        """``P(collapse | IM = intensity)`` of the fitted lognormal (0 at intensity 0).

        Examples
        --------
        >>> from duhamel.ensemble import fit_fragility
        >>> frag = fit_fragility([1.0, 2.0, 4.0])
        >>> float(frag.probability(2.0))          # the median
        0.5
        """
        from scipy.special import ndtr

        x = as_float_array(intensity, "intensity", finite=False)
        if np.isnan(x).any() or np.any(x < 0):
            raise ValueError(f"`intensity` must be >= 0 (inf allowed), got {intensity!r}")
        with np.errstate(divide="ignore"):
            return ndtr(np.log(x / self.median) / self.beta)

    def plot(self, ax: Any = None, label: str = "intensity") -> Any:
        """The fitted CDF and the empirical fraction of records collapsed (each collapse
        intensity at ``(i - 0.5) / n``); returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4.5))
        x = np.sort(self.collapse_intensities)
        n = x.size
        finite = np.isfinite(x)
        ax.plot(x[finite], (np.arange(1, n + 1)[finite] - 0.5) / n, "o", ms=4, color="k",
                label="records")  # fmt: skip
        top = np.nanmax(np.r_[x[finite], self.censored_at or 0.0, self.median]) * 1.2
        grid = np.linspace(0.0, top, 200)
        ax.plot(grid, self.probability(grid), lw=2,
                label=f"lognormal ({self.method}): median {self.median:.3g}, "
                f"beta {self.beta:.2f}")  # fmt: skip
        if self.mce is not None:
            ax.axvline(self.mce, color="0.4", ls="--", label=f"MCE (CMR {self.cmr:.2f})")
        ax.set_xlabel(label)
        ax.set_ylabel("P(collapse)")
        ax.set_ylim(0.0, 1.0)
        ax.legend(fontsize="small")
        ax.grid(True, alpha=0.3)
        return ax


def _censored_mle(ln_x: NDArray, ln_c: float, n_censored: int) -> tuple[float, float]:
    """Maximum likelihood of ``(ln median, beta)`` with `n_censored` records right-censored
    at ``ln_c`` (Baker 2015, eq. 11)."""
    from scipy.optimize import minimize
    from scipy.special import log_ndtr

    def nll(p: NDArray) -> float:
        mu, beta = p[0], np.exp(p[1])
        z = (ln_x - mu) / beta
        return float(
            0.5 * np.sum(z * z)
            + ln_x.size * np.log(beta)
            - n_censored * log_ndtr(-(ln_c - mu) / beta)
        )

    start = np.array([ln_x.mean(), np.log(max(ln_x.std(), 1e-3))])
    res = minimize(nll, start, method="Nelder-Mead",
                   options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": 20000})  # fmt: skip
    if not res.success:
        raise ValueError(f"the censored maximum-likelihood fit did not converge: {res.message}")
    return float(res.x[0]), float(np.exp(res.x[1]))


def fit_fragility(
    collapse_intensities: ArrayLike,
    method: str = "mle",
    *,
    censored_at: float | None = None,
    mce: float | None = None,
) -> Fragility:
    """Fit a lognormal collapse fragility to the records' collapse intensities.

    Parameters
    ----------
    collapse_intensities : array_like
        One positive intensity per record; ``inf`` for a record that had not collapsed at
        the largest intensity run (then `censored_at` is required and `method` must be
        ``'mle'``).
    method : {'mle', 'moments'}
        Maximum likelihood (Baker 2015; right-censored records in the likelihood) or the
        method of moments on the logarithms (sample standard deviation, ``n - 1``).
    censored_at : float, optional
        The largest intensity run: the records marked ``inf`` survived it.
    mce : float, optional
        The MCE intensity ``S_MT`` (same units): gives :attr:`Fragility.cmr`.

    Returns
    -------
    Fragility

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.ensemble import fit_fragility
    >>> frag = fit_fragility([0.5, 1.0, 2.0], mce=0.4)    # ln x = -ln 2, 0, ln 2
    >>> float(frag.median), bool(np.isclose(frag.beta, np.log(2) * np.sqrt(2 / 3)))
    (1.0, True)
    >>> float(frag.cmr)                                    # FEMA P695: median / S_MT
    2.5
    >>> frag = fit_fragility([0.5, 1.0, 2.0], "moments")   # sample std: n - 1
    >>> bool(np.isclose(frag.beta, np.log(2)))
    True
    """
    x = np.atleast_1d(as_float_array(collapse_intensities, "collapse_intensities", finite=False))
    if x.ndim != 1 or np.isnan(x).any() or np.any(x <= 0):
        raise ValueError(
            "`collapse_intensities` must be a 1-D array of positive intensities (inf for a "
            f"record that did not collapse), got {collapse_intensities!r}"
        )
    if not isinstance(method, str) or method not in ("mle", "moments"):
        raise ValueError(f"`method` must be 'mle' or 'moments', got {method!r}")
    if mce is not None:
        mce = positive_float(mce, "mce")
    collapsed = np.isfinite(x)
    n_censored = int((~collapsed).sum())
    if censored_at is not None:
        censored_at = positive_float(censored_at, "censored_at")
        if np.any(x[collapsed] > censored_at):
            raise ValueError(
                f"`collapse_intensities` has values above `censored_at` = {censored_at}: the "
                "records that collapsed cannot lie beyond the largest intensity run"
            )
    if n_censored and censored_at is None:
        raise ValueError(
            f"{n_censored} record(s) did not collapse (inf): give `censored_at`, the largest "
            "intensity they survived"
        )
    if n_censored and method == "moments":
        raise ValueError(
            f"method='moments' needs every record to have collapsed ({n_censored} did not): "
            "use method='mle', which treats them as right-censored"
        )
    ln_x = np.log(x[collapsed])
    if ln_x.size < 2 or np.ptp(ln_x) == 0.0:
        raise ValueError(
            "`collapse_intensities` must hold at least two different finite collapse "
            f"intensities to fit a dispersion, got {collapse_intensities!r}"
        )
    if n_censored:
        mu, beta = _censored_mle(ln_x, float(np.log(censored_at)), n_censored)  # type: ignore[arg-type]
    else:
        mu = float(ln_x.mean())
        beta = float(ln_x.std(ddof=0 if method == "mle" else 1))
    return Fragility(float(np.exp(mu)), beta, method, x, censored_at, mce)
