"""Spectral radius against dt/T: the data of the paper's Figs. 1 and 2, and their plot."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import elements
from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.analysis._linear import modal_model
from duhamel.analysis.matrices import ClosedFormNewmark, _alpha_sign, amplification_eigenvalues
from duhamel.integrators import Semianalytic
from duhamel.system import System

__all__ = ["StabilityChart", "model_oscillator", "plot_stability_chart", "stability_chart"]

Array = NDArray[np.float64]
Damping = Literal["pseudo-force", "background"]


def model_oscillator(
    omega: float = 1.0,
    zeta: float = 0.1,
    *,
    alpha: float = 0.0,
    alpha_sign: int = 1,
    damping: Damping = "pseudo-force",
) -> System:
    """The paper's model oscillator ``X'' + 2 zeta omega X' + omega^2 X = s alpha omega^2 X``.

    Parameters
    ----------
    omega : float
        Natural frequency of the background, > 0 (``T = 2 pi / omega``).
    zeta : float
        Damping ratio.
    alpha : float
        The extra stiffness term of eq. 25 (0: eq. 18). It always enters as a pseudo-force, a
        ``Spring`` to ground of stiffness ``-s alpha omega^2``.
    alpha_sign : {+1, -1}
        ``s``: +1 is the right-hand side ``+alpha omega^2 X``, the form with which the
        paper's eqs. 26 and 27 are consistent (effective stiffness ``(1 - alpha) omega^2``);
        -1 is the form printed in eq. 25 (``(1 + alpha) omega^2``).
    damping : {"pseudo-force", "background"}
        "pseudo-force": an undamped background plus a ``Damper`` ``2 zeta omega`` (eq. 18,
        Fig. 1; a ``LinearCoupling`` when ``zeta < 0``). "background": the damping stays in
        the exact background, ``System(..., zeta=zeta)`` (eq. 25 and Fig. 2, for which the
        paper uses the damped transfer matrix of its eq. 10).

    Returns
    -------
    System

    Examples
    --------
    >>> from duhamel.analysis import model_oscillator
    >>> model_oscillator(zeta=0.1)
    System(n_dof=1, damping='none', loads=0, elements=1)
    >>> model_oscillator(zeta=0.1, alpha=0.3, damping="background")
    System(n_dof=1, damping='zeta', loads=0, elements=1)
    """
    omega = positive_float(omega, "omega")
    zeta = finite_float(zeta, "zeta")
    alpha = finite_float(alpha, "alpha")
    sign = _alpha_sign(alpha_sign)
    if damping not in ("pseudo-force", "background"):
        raise ValueError(f"`damping` must be 'pseudo-force' or 'background', got {damping!r}")
    w2 = omega * omega
    if damping == "background":
        system = System([[1.0]], [[w2]], zeta=zeta)
    else:
        system = System([[1.0]], [[w2]])
        c = 2.0 * zeta * omega
        if c > 0.0:
            system.add(elements.Damper(0, c=c))
        elif c < 0.0:
            system.add(elements.LinearCoupling(C=np.array([[c]])))
    if alpha != 0.0:
        system.add(elements.Spring(0, k=-sign * alpha * w2))
    return system


def _label(integrator: Any) -> str:
    if isinstance(integrator, Semianalytic):
        return f"scheme ({integrator.scheme})"
    if isinstance(integrator, ClosedFormNewmark):
        return f"Newmark (gamma={integrator.gamma:g}, beta={integrator.beta:g})"
    return type(integrator).__name__


def _moduli(system: System, integrator: Any, dt: float) -> Array:
    lam = amplification_eigenvalues(system, integrator, dt)
    return np.sort(np.abs(lam))[::-1]


@dataclass(frozen=True, eq=False)
class StabilityChart:
    """Eigenvalue moduli of the amplification matrices over a range of ``dt/T``.

    Attributes
    ----------
    dt_over_T : ndarray, shape (k,)
        Steps divided by the undamped period ``T = 2 pi / omega`` of the background.
    labels : tuple of str
        One per integrator.
    integrators : tuple
        The integrators, in the order of `labels`.
    moduli : ndarray, shape (n_integrators, k, m)
        Moduli of the eigenvalues of each step (:func:`amplification_eigenvalues`), largest
        first: ``m = 2`` for one-step methods of ``(x, v)``, 3 for HHT-alpha and
        generalized-alpha (padded with NaN where fewer are found).
    exact : ndarray, shape (k,)
        Spectral radius of the exact transition matrix (``exp(-zeta omega dt)`` when
        underdamped).
    system : System
        The model oscillator (:func:`model_oscillator`).
    omega, zeta, alpha, alpha_sign, damping
        The model's parameters.
    """

    dt_over_T: Array
    labels: tuple[str, ...]
    integrators: tuple[Any, ...]
    moduli: Array
    exact: Array
    system: System
    omega: float
    zeta: float
    alpha: float
    alpha_sign: int
    damping: Damping

    @property
    def radius(self) -> Array:
        """Spectral radii, shape ``(n_integrators, k)``."""
        return self.moduli[..., 0]

    def _index(self, label: str) -> int:
        if label not in self.labels:
            raise ValueError(f"`label` must be one of {list(self.labels)}, got {label!r}")
        return self.labels.index(label)

    def curve(self, label: str) -> Array:
        """The spectral radius of the integrator `label` on the grid, shape ``(k,)``."""
        return self.radius[self._index(label)]

    def spectral_radius(self, label: str, dt_over_T: float) -> float:
        """The spectral radius of the integrator `label` at any ``dt/T`` (> 0)."""
        x = positive_float(dt_over_T, "dt_over_T")
        integrator = self.integrators[self._index(label)]
        return float(_moduli(self.system, integrator, x * 2.0 * np.pi / self.omega)[0])

    def unstable_intervals(self, label: str, *, tol: float = 1e-10) -> list[tuple[float, float]]:
        """The intervals of ``dt/T`` on which the spectral radius exceeds ``1 + tol``.

        Sign changes of ``rho - 1 - tol`` between neighbouring grid points are refined by
        Brent's method on ``rho(dt/T)`` (to about 1e-13 relative), so the ends do not depend
        on the grid spacing; an interval narrower than the grid spacing can be missed, and
        one still open at an end of the grid ends there. `tol` keeps the points where the
        spectral radius touches 1 exactly (e.g. scheme (b) at ``dt/T = k/2``) out.

        Returns
        -------
        list of (float, float)
        """
        import scipy.optimize  # 0.4 s to import: only where a root is refined

        tol = finite_float(tol, "tol")
        x = self.dt_over_T
        g = self.curve(label) - 1.0 - tol

        def excess(v: float) -> float:
            return self.spectral_radius(label, v) - 1.0 - tol

        ends = [x[0]] if g[0] > 0 else []
        for i in np.flatnonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0):
            root = scipy.optimize.brentq(excess, x[i], x[i + 1], xtol=1e-15, rtol=1e-13)
            ends.append(float(root))
        if len(ends) % 2:
            ends.append(float(x[-1]))
        return [(float(ends[i]), float(ends[i + 1])) for i in range(0, len(ends), 2)]

    def peak(self, label: str) -> tuple[float, float]:
        """The largest spectral radius of `label` over the grid's range, refined.

        The grid's local maxima within 5 % of the largest are refined by bounded Brent
        minimisation between their neighbours (a peak narrower than the grid spacing can be
        missed); of equal maxima (to 1e-12, e.g. a periodic
        curve) the one at the smallest ``dt/T`` is reported.

        Returns
        -------
        (float, float)
            ``dt/T`` and the spectral radius there.
        """
        import scipy.optimize

        x, rho = self.dt_over_T, self.curve(label)
        top = float(rho.max())
        found = [(float(x[np.argmax(rho)]), top)]
        for i in range(1, x.size - 1):
            if rho[i] >= rho[i - 1] and rho[i] >= rho[i + 1] and rho[i] >= 0.95 * top:
                res = scipy.optimize.minimize_scalar(
                    lambda v: -self.spectral_radius(label, v),
                    bounds=(x[i - 1], x[i + 1]),
                    method="bounded",
                    options={"xatol": 1e-12 * x[i]},
                )
                found.append((float(res.x), float(-res.fun)))
        best = max(value for _, value in found)
        return min((where, value) for where, value in found if value >= best - 1e-12 * best)


def stability_chart(
    integrators: Mapping[str, Any] | Sequence[Any],
    dt_over_T: ArrayLike,
    zeta: float = 0.1,
    *,
    alpha: float = 0.0,
    alpha_sign: int = 1,
    damping: Damping = "pseudo-force",
    omega: float = 1.0,
) -> StabilityChart:
    """Spectral radius against ``dt/T`` on the paper's model oscillator (its Figs. 1 and 2).

    For each integrator and each ``dt/T``, the eigenvalue moduli of its step
    (:func:`~duhamel.analysis.amplification_eigenvalues`: the amplification matrix, or the
    realized step of an integrator that carries its acceleration) on
    :func:`model_oscillator`, with ``dt = (dt/T) 2 pi / omega``.

    Parameters
    ----------
    integrators : mapping of label to integrator, or sequence of integrators
        Anything :func:`duhamel.solve` accepts, or
        :class:`~duhamel.analysis.ClosedFormNewmark`. A sequence is labelled automatically
        (``"scheme (b)"``, ``"Newmark (gamma=0.5, beta=0.25)"``, the class name).
    dt_over_T : array_like, shape (k,)
        Increasing positive steps over the undamped period of the background (for the
        paper's range, ``np.logspace(-3, 3, 1201)``).
    zeta : float
        Damping ratio.
    alpha : float
        Eq. 25's extra stiffness term (0: Fig. 1's eq. 18).
    alpha_sign : {+1, -1}
        Sign of eq. 25's right-hand side ``s alpha omega^2 X``: +1 (default) is consistent
        with eqs. 26 and 27, -1 is the printed eq. 25; see :func:`model_oscillator`.
    damping : {"pseudo-force", "background"}
        Where the damping goes: the right-hand side (Fig. 1, the default) or the exact
        background (Fig. 2).
    omega : float
        Natural frequency (the chart does not depend on it).

    Returns
    -------
    StabilityChart

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import stability_chart
    >>> chart = stability_chart([duhamel.Semianalytic(scheme="a")], np.logspace(-1, 0.5, 61))
    >>> chart.labels
    ('scheme (a)',)
    >>> [tuple(round(v, 6) for v in i) for i in chart.unstable_intervals("scheme (a)")]
    [(0.5, 1.0), (1.5, 2.0), (2.5, 3.0)]
    >>> round(chart.peak("scheme (a)")[1], 6)
    1.105542
    """
    if isinstance(integrators, Mapping):
        labels = [str(k) for k in integrators]
        items = list(integrators.values())
    elif isinstance(integrators, Sequence) and not isinstance(integrators, str):
        items = list(integrators)
        base = [_label(i) for i in items]
        labels = [
            f"{name} #{base[:i].count(name) + 1}" if base[:i].count(name) else name
            for i, name in enumerate(base)
        ]
    else:
        raise TypeError(
            "`integrators` must be a mapping of labels to integrators or a sequence of "
            f"integrators, got {type(integrators).__name__}"
        )
    if not items:
        raise ValueError("`integrators` must not be empty")
    x = as_float_array(dt_over_T, "dt_over_T", ndim=1)
    if x.size < 2 or np.any(x <= 0.0) or np.any(np.diff(x) <= 0.0):
        raise ValueError("`dt_over_T` must hold at least two increasing positive values")
    system = model_oscillator(omega, zeta, alpha=alpha, alpha_sign=alpha_sign, damping=damping)
    omega, zeta, alpha = float(omega), float(zeta), float(alpha)
    period = 2.0 * np.pi / omega
    rows = [[_moduli(system, it, v * period) for v in x] for it in items]
    width = max(r.size for row in rows for r in row)
    moduli = np.full((len(items), x.size, width), np.nan)
    for i, row in enumerate(rows):
        for j, r in enumerate(row):
            moduli[i, j, : r.size] = r
    growth = float(np.max(np.linalg.eigvals(modal_model(system).state_matrix()).real))
    return StabilityChart(
        dt_over_T=x,
        labels=tuple(labels),
        integrators=tuple(items),
        moduli=moduli,
        exact=np.exp(growth * x * period),
        system=system,
        omega=omega,
        zeta=zeta,
        alpha=alpha,
        alpha_sign=int(alpha_sign),
        damping=damping,
    )


def plot_stability_chart(
    data: StabilityChart, ax: Any = None, *, exact: bool = True, moduli: bool = False
) -> Any:
    """Draw a :class:`StabilityChart`: ``|lambda|`` against ``dt/T`` on a logarithmic axis.

    Parameters
    ----------
    data : StabilityChart
    ax : matplotlib Axes, sequence of Axes, or None
        None: a new figure with one panel per integrator (the paper's Fig. 1 (a)-(c));
        one Axes: every curve in it (Fig. 2); a sequence: one Axes per integrator.
    exact : bool
        Also draw the exact solution's ``|lambda| = exp(Re(s) dt)``.
    moduli : bool
        Also draw the smaller eigenvalue moduli (they differ from the spectral radius where
        the eigenvalues are real, and for the spurious roots of HHT-alpha and the like).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import plot_stability_chart, stability_chart
    >>> chart = stability_chart([duhamel.Semianalytic(scheme=s) for s in "abc"],
    ...                         np.logspace(-1, 1, 41))
    >>> fig = plot_stability_chart(chart)
    >>> len(fig.axes)
    3
    """
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ImportError("plotting needs matplotlib: pip install 'duhamel[plot]'") from exc
    if not isinstance(data, StabilityChart):
        raise TypeError(f"`data` must be a StabilityChart, got {type(data).__name__}")
    n = len(data.labels)
    if ax is None:
        fig, axes = plt.subplots(1, n, figsize=(3.3 * n + 0.6, 3.1), sharey=True, squeeze=False)
        panels = list(axes[0])
        where = "damping as pseudo-force" if data.damping == "pseudo-force" else "damped background"
        extra = rf", $\alpha$ = {data.alpha:g} (sign {data.alpha_sign:+d})" if data.alpha else ""
        fig.suptitle(rf"$\zeta$ = {data.zeta:g}, {where}{extra}", fontsize=10)
    elif isinstance(ax, Sequence):
        if len(ax) != n:
            raise ValueError(f"`ax` must hold one Axes per integrator ({n}), got {len(ax)}")
        panels = list(ax)
    else:
        panels = [ax] * n
    x = data.dt_over_T
    for i, (panel, label) in enumerate(zip(panels, data.labels, strict=True)):
        shared = panels.count(panel) > 1
        color = f"C{i}" if shared else "k"
        panel.semilogx(x, data.moduli[i, :, 0], color=color, lw=1.2, label=label)
        if moduli:
            for j in range(1, data.moduli.shape[2]):
                panel.semilogx(x, data.moduli[i, :, j], color=color, lw=0.6, alpha=0.5)
        first = panels.index(panel) == i
        if first:
            if exact:
                panel.semilogx(x, data.exact, "--", color="0.45", lw=1.0, label="exact")
            panel.axhline(1.0, color="0.7", lw=0.6, ls=":")
            panel.set_xlabel(r"$\Delta t\,/\,T$")
            panel.grid(True, which="major", alpha=0.3)
        if not shared:
            panel.set_title(label, fontsize=10)
    panels[0].set_ylabel(r"$|\lambda|$")
    for panel in dict.fromkeys(panels):
        panel.legend(fontsize=8, loc="lower left")
    fig = panels[0].figure
    if ax is None:
        fig.tight_layout()
    return fig
