"""Active magnetic bearings: the rotor and its bearing controllers as one linear first-order
system (closed-loop modes, frequency responses, the sensitivity function, transients).

In each direction (x, y) of its node a :class:`MagneticBearing` pushes the rotor with
``f = k_s x + k_i i`` (``k_s > 0`` the open-loop negative stiffness, as ROSS writes it) and
its current is ``i = -C(s) e``, ``e`` the measured displacement (``x``, plus a sensor
disturbance ``d`` for the sensitivity function). ``C(s)`` is a :class:`PID`
``kp + ki / s + kd s / (1 + tau s)`` or any chain of the state-space blocks of
:mod:`duhamel.rotor.controllers` (sensor, PID, low-pass, notch, amplifier...), whose
realization ``z' = A_c z + B_c e``, ``C(s) e = C_c z + D_c e`` supplies the controller states
(the PID's: the integral of ``e`` when ``ki != 0``, the derivative's filter
``z' = (e - z) / tau`` when ``kd != 0``). With the rotor's
``M x'' + (C + speed G) x' + K x = f`` the closed loop is

    s' = A s + B f_ext,    s = (x, x', controller states),

assembled here; everything below is exact for it: eigenvalues (``scipy.linalg.eig``),
receptances (one complex solve per frequency), the sensitivity ``S = e / d`` of each bearing
axis, and transients by the first-order hold discretisation ``expm`` of the augmented matrix
(Van Loan), exact for forces linear between the samples.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, nonneg_float, positive_float
from duhamel.rotor.controllers import PID, ControllerBlock, Series

__all__ = [
    "PID",
    "ClosedLoop",
    "MagneticBearing",
    "MarginalWarning",
    "closed_loop",
    "feedback",
    "split_magnetic",
]


class MarginalWarning(UserWarning):
    """A closed loop is marginally stable (eigenvalues on the imaginary axis to round-off):
    its harmonic responses are computed, and said to be of a marginal loop."""


@dataclass(frozen=True)
class MagneticBearing:
    """An active magnetic bearing at a node, the same in x and y.

    Parameters
    ----------
    node : int
    k_i : float
        Current stiffness (N/A), > 0.
    k_s : float
        Open-loop negative stiffness (N/m), >= 0: the force is ``+k_s x``.
    controller : PID, controller block, or sequence of blocks
        ``C(s)`` from the measured displacement to the current: a :class:`PID`, any block of
        :mod:`duhamel.rotor.controllers` (:class:`~duhamel.rotor.controllers.LowPass`,
        :class:`~duhamel.rotor.controllers.Notch`, :class:`~duhamel.rotor.controllers.Sensor`,
        :class:`~duhamel.rotor.controllers.Amplifier`,
        :class:`~duhamel.rotor.controllers.StateSpace`), or several in series (a sequence
        becomes a :class:`~duhamel.rotor.controllers.Series`).

    Examples
    --------
    >>> from duhamel.rotor import PID, LowPass, MagneticBearing, Notch, Sensor
    >>> amb = MagneticBearing(0, k_i=100.0, k_s=1e6,
    ...                       controller=[Sensor(bandwidth=3e4), PID(3e4, 1e5, 30.0, 1e-4),
    ...                                   LowPass(8e3, order=2), Notch(900.0)])
    >>> amb.controller.n_states
    7
    """

    node: int
    k_i: float
    k_s: float
    controller: Any

    def __post_init__(self) -> None:
        if isinstance(self.node, bool) or not isinstance(self.node, int | np.integer):
            raise TypeError(f"`node` must be an integer, got {self.node!r}")
        object.__setattr__(self, "k_i", positive_float(self.k_i, "k_i"))
        object.__setattr__(self, "k_s", nonneg_float(self.k_s, "k_s"))
        c = self.controller
        if isinstance(c, list | tuple) and all(isinstance(b, ControllerBlock) for b in c):
            c = Series(*c)
        if not isinstance(c, ControllerBlock):
            raise TypeError(
                "`controller` must be a PID or another controller block (or a sequence of "
                f"them), got {type(c).__name__}"
            )
        object.__setattr__(self, "controller", c)


def feedback(bearings: Sequence[MagneticBearing], dof: Callable, n_dof: int) -> Any:
    """The bearings' closed loops as a :class:`duhamel.feedback.Feedback` on a System of
    `n_dof` dofs: per axis (dof ``j``) the direct feedback ``k_i D_c - k_s`` in ``K_d`` and
    the controller's states ``z' = A_c z + B_c x_j`` pushing with ``k_i C_c z``."""
    from duhamel.feedback import Feedback

    axes = [(int(dof(b.node, a)), b) for b in bearings for a in ("x", "y")]
    blocks = [b.controller.state_space() for _, b in axes]
    nz = int(sum(a.shape[0] for a, _, _, _ in blocks))
    Kd = np.zeros((n_dof, n_dof))
    A, B, F = np.zeros((nz, nz)), np.zeros((nz, n_dof)), np.zeros((n_dof, nz))
    row = 0
    for (j, b), (Ac, Bc, Cc, Dc) in zip(axes, blocks, strict=True):
        z = slice(row, row + Ac.shape[0])
        Kd[j, j] += b.k_i * Dc - b.k_s
        A[z, z], B[z, j], F[j, z] = Ac, Bc, b.k_i * Cc
        row += Ac.shape[0]
    if nz == 0:  # static controllers only: one inert state keeps the form
        A, B, F = -np.ones((1, 1)), np.zeros((1, n_dof)), np.zeros((n_dof, 1))
    return Feedback(K=Kd, A=A, B=B, F=F)


def split_magnetic(items: Sequence[Any]) -> tuple[list[Any], tuple[MagneticBearing, ...]]:
    """`items` as the other bearings and the magnetic ones."""
    magnetic = tuple(b for b in items if isinstance(b, MagneticBearing))
    return [b for b in items if not isinstance(b, MagneticBearing)], magnetic


@dataclass(frozen=True, eq=False)
class ClosedLoop:
    """The rotor with its magnetic bearings' controllers: ``s' = A s + B f``.

    Attributes
    ----------
    A : ndarray, shape (n_states, n_states)
    n_dof : int
        Rotor dofs: ``s[:n_dof]`` displacements, ``s[n_dof:2 n_dof]`` velocities, then the
        controller states.
    axes : tuple of (int, MagneticBearing)
        Each bearing axis: its dof and its bearing.
    """

    A: NDArray[np.float64]
    n_dof: int
    axes: tuple[tuple[int, MagneticBearing], ...]
    M_inv: NDArray[np.float64]
    _E: NDArray[np.float64]  # disturbance input of each axis (the measured-signal channel)

    @cached_property
    def _spectrum(self) -> Any:
        from duhamel.rotor._roundoff import spectrum

        return spectrum(self.A)

    @cached_property
    def eigenvalues(self) -> NDArray[np.complex128]:
        """Closed-loop eigenvalues, sorted by imaginary then real part."""
        lam = self._spectrum.eigenvalues
        return lam[np.lexsort((lam.real, lam.imag))]

    @property
    def stability(self) -> str:
        """``"stable"``, ``"marginal"`` or ``"unstable"``, each eigenvalue's real part judged
        against the round-off the eigensolver can make in it
        (:mod:`duhamel.rotor._roundoff`): a loop whose bearings hold a rigid-body mode with
        zero net stiffness (ROSS's ``rotor_amb_example``: ``k_i k_p = -k_s``) is marginal,
        not unstable."""
        return str(self._spectrum.verdict)

    @property
    def stability_note(self) -> str:
        """:attr:`stability` in a sentence, with the eigenvalues behind it."""
        return str(self._spectrum.describe())

    @property
    def stable(self) -> bool:
        """Whether every eigenvalue decays beyond round-off (:attr:`stability` is
        ``"stable"``; a marginal loop is not)."""
        return self.stability == "stable"

    def force_input(self, dofs: Sequence[int]) -> NDArray[np.float64]:
        """``B`` for unit forces on `dofs`: ``M^-1`` columns in the velocity rows."""
        B = np.zeros((self.A.shape[0], len(dofs)))
        B[self.n_dof : 2 * self.n_dof] = self.M_inv[:, list(dofs)]
        return B

    def frequency_response(
        self, frequencies: ArrayLike, inputs: Sequence[int], outputs: Sequence[int]
    ) -> NDArray[np.complex128]:
        """Closed-loop receptances ``(n_frequencies, n_outputs, n_inputs)``: ``x_o =
        Re(H F e^{i w t})`` for forces ``Re(F e^{i w t})`` on the `inputs` dofs (a stable
        loop only: an unstable one raises ``ValueError``, as :meth:`sensitivity` does)."""
        return self._response(frequencies, self.force_input(inputs), list(outputs))

    def _response(self, frequencies: ArrayLike, B: NDArray, rows: list[int]) -> NDArray:
        ws = as_float_array(frequencies, "frequencies", ndim=1)
        if self.stability == "unstable":
            raise ValueError(
                f"the closed loop is {self.stability_note}; its frequency response and "
                "sensitivity are no steady state; see `eigenvalues`"
            )
        if self.stability == "marginal":
            import warnings

            warnings.warn(
                f"the closed loop is {self.stability_note}: the harmonic response is that of "
                "the decaying and oscillating modes",
                MarginalWarning,
                stacklevel=3,
            )
        n = self.A.shape[0]
        out = np.empty((ws.size, len(rows), B.shape[1]), dtype=complex)
        for k, w in enumerate(ws):
            out[k] = np.linalg.solve(1j * w * np.eye(n) - self.A, B)[rows]
        return out

    def sensitivity(self, frequencies: ArrayLike) -> NDArray[np.complex128]:
        """Sensitivity ``S = e / d`` of each bearing axis, ``(n_frequencies, n_axes)``: a
        disturbance ``d`` added to the axis's measured displacement, the loop closed (the
        other axes closed too); for one axis ``S = 1 / (1 + L)``."""
        rows = [dof for dof, _ in self.axes]
        x = self._response(frequencies, self._E, rows)
        return 1.0 + np.einsum("kaa->ka", x)

    def peak_sensitivity(self, frequencies: ArrayLike) -> tuple[float, float, int]:
        """The largest ``|S|`` over the axes and `frequencies`: ``(peak, frequency, axis)``
        (ISO 14839-3 zones: A below 3, B below 4, C below 5)."""
        ws = as_float_array(frequencies, "frequencies", ndim=1)
        mag = np.abs(self.sensitivity(ws))
        k, a = np.unravel_index(int(np.argmax(mag)), mag.shape)
        return float(mag[k, a]), float(ws[k]), int(a)

    def transient(
        self,
        t: ArrayLike,
        forces: NDArray[np.float64] | None = None,
        dofs: Sequence[int] = (),
        *,
        x0: ArrayLike | None = None,
        v0: ArrayLike | None = None,
        elements: Sequence[Any] = (),
        tol: float = 1e-10,
        max_iter: int = 50,
    ) -> NDArray[np.float64]:
        """States at the equally spaced times `t`, forces ``(len(t), len(dofs))`` linear
        between the samples: ``s[n+1] = Ad s[n] + B0 f[n] + B1 f[n+1]`` from ``expm`` of
        Van Loan's augmented matrix, exact for such forces. Returns ``(len(t), n_states)``.

        With `elements` (duhamel elements on the rotor's dofs: a rub
        :class:`~duhamel.elements.Contact`, a cubic :class:`~duhamel.elements.Spring`...)
        their forces act on top of the closed loop as pseudo-forces: the Rust core's
        first-order route on the closed loop's own modes
        (:mod:`duhamel.rotor._closed_loop_run`), the linear loop exact, the elements'
        forces second order in the step (Newton to `tol`, at most `max_iter` iterations).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> from duhamel.rotor import PID, STEEL, Disk, MagneticBearing, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 20.0, 0.3, 0.15)])
        >>> amb = [MagneticBearing(n, 100.0, 1e6, PID(3e4, 1e5, 30.0, 1e-4)) for n in (0, 4)]
        >>> loop = rotor.closed_loop(400.0, amb)
        >>> rub = duhamel.elements.Contact(
        ...     (rotor.dof(2, "x"), rotor.dof(2, "y")), clearance=1e-5, stiffness=1e8
        ... )
        >>> t = np.linspace(0.0, 0.02, 801)  # the route stops beyond omega_c dt = 0.5
        >>> f = np.full((t.size, 1), 2e3)
        >>> s = loop.transient(t, f, [rotor.dof(2, "x")], elements=[rub])
        >>> x = s[-1, rotor.dof(2, "x")]   # 2 kN: 1 mm without the stator, 29 um with it
        >>> bool(2e-5 < x < 4e-5)
        True
        """
        import scipy.linalg

        ts = as_float_array(t, "t", ndim=1)
        h = float(ts[1] - ts[0]) if ts.size > 1 else 0.0
        if ts.size < 2 or h <= 0 or not np.allclose(np.diff(ts), h, rtol=1e-12, atol=0.0):
            raise ValueError("`t` must be at least two equally spaced increasing times")
        n = self.A.shape[0]
        B = self.force_input(dofs)
        m = B.shape[1]
        f = np.zeros((ts.size, m)) if forces is None else np.asarray(forces, dtype=float)
        if f.shape != (ts.size, m):
            raise ValueError(f"`forces` must have shape (len(t), len(dofs)) = {(ts.size, m)}")
        s = np.zeros((ts.size, n))
        s[0, : self.n_dof] = 0.0 if x0 is None else as_float_array(x0, "x0", ndim=1)
        s[0, self.n_dof : 2 * self.n_dof] = 0.0 if v0 is None else as_float_array(v0, "v0", ndim=1)
        if elements:
            from duhamel.rotor._closed_loop_run import transient_with_elements

            s = transient_with_elements(
                self.A, self.force_input(range(self.n_dof)), s[0], ts, f, list(dofs),
                list(elements), tol=tol, max_iter=max_iter,
            )  # fmt: skip
            if not np.all(np.isfinite(s)):
                raise ValueError("the closed-loop transient is not finite (an unstable tuning?)")
            return s
        big = np.zeros((n + 2 * m, n + 2 * m))
        big[:n, :n] = self.A * h
        big[:n, n : n + m] = B * h
        big[n : n + m, n + m :] = np.eye(m)
        E = scipy.linalg.expm(big)
        Ad, G1, G2 = E[:n, :n], E[:n, n : n + m], E[:n, n + m :]
        B0, B1 = G1 - G2, G2
        for k in range(ts.size - 1):
            s[k + 1] = Ad @ s[k] + B0 @ f[k] + B1 @ f[k + 1]
        if not np.all(np.isfinite(s)):
            raise ValueError("the closed-loop transient is not finite (an unstable tuning?)")
        return s


def closed_loop(
    matrices: tuple, bearings: Sequence[MagneticBearing], speed: float, *, dof: Callable
) -> ClosedLoop:
    """The closed loop of the rotor ``(M, K, C, G)`` at `speed` with `bearings`."""
    import scipy.linalg

    M, K, C, G = (np.asarray(a, dtype=float) for a in matrices)
    n = M.shape[0]
    w = finite_float(speed, "speed")
    try:
        M_inv = scipy.linalg.inv(M)
    except (np.linalg.LinAlgError, ValueError):
        raise ValueError("the mass matrix is singular (massless dofs): no closed loop") from None
    axes = []
    for b in bearings:
        if not isinstance(b, MagneticBearing):
            raise TypeError(f"`bearings` must hold MagneticBearing, got {type(b).__name__}")
        axes += [(int(dof(b.node, "x")), b), (int(dof(b.node, "y")), b)]
    sizes = [b.controller.state_space()[0].shape[0] for _, b in axes]
    nc = int(sum(sizes))
    N = 2 * n + nc
    A = np.zeros((N, N))
    A[:n, n : 2 * n] = np.eye(n)
    A[n : 2 * n, :n] = -M_inv @ K
    A[n : 2 * n, n : 2 * n] = -M_inv @ (C + w * G)
    E = np.zeros((N, len(axes)))  # the disturbance d of each axis, added to its measurement
    row = 2 * n
    for a, ((j, b), size) in enumerate(zip(axes, sizes, strict=True)):
        Ac, Bc, Cc, Dc = b.controller.state_space()
        ctrl = slice(row, row + size)
        # force on dof j: k_s x_j + k_i i,  i = -(Cc z + Dc e),  e = x_j + d
        coupling = np.zeros(N)
        coupling[j] += b.k_s - b.k_i * Dc
        coupling[ctrl] += -b.k_i * Cc
        A[n : 2 * n] += np.outer(M_inv[:, j], coupling)
        E[n : 2 * n, a] += M_inv[:, j] * (-b.k_i * Dc)
        A[ctrl, ctrl] = Ac
        A[ctrl, j] += Bc
        E[ctrl, a] += Bc
        row += size
    return ClosedLoop(A, n, tuple(axes), M_inv, E)
