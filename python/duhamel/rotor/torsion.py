"""Torsional vibration of a rotor (a drive train): one twist angle per node.

Each :class:`~duhamel.rotor.Shaft` of a :class:`~duhamel.rotor.Rotor` is a torsion element
of polar moment of area ``J_p = pi (d_o^4 - d_i^4) / 32``: stiffness ``G J_p / L`` and the
consistent inertia ``rho J_p L / 6 [[2, 1], [1, 2]]`` (the linear shape functions; ROSS's
shaft element has the same two matrices on its torsional dofs); each
:class:`~duhamel.rotor.Disk` adds its polar inertia ``Ip`` at its node. Couplings (a flexible
coupling, a gear mesh reduced to one shaft line) are extra torsional springs between two
nodes. Bearings carry no torque: the free train has a rigid-body mode (zero frequency), which
:meth:`Torsion.modes` lists apart. Lateral and torsional motion are uncoupled in this linear
model (as in ROSS for axisymmetric elements), so the torsional natural frequencies do not
depend on the spin speed: the torsional Campbell diagram is horizontal lines, and its
critical speeds are where an excitation order crosses them.

Transients: :meth:`Torsion.system` is a :class:`duhamel.System` on the twist angles; torques
are loads on its dofs (:meth:`Torsion.dof`), e.g. a synchronous motor's start-up torque
(:func:`startup_torque`) or a short-circuit air-gap torque (:func:`short_circuit_torque`),
both ``duhamel.loads.Tabulated``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import KW_ONLY, dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.rotor.campbell import Campbell

__all__ = [
    "Torsion",
    "TorsionalCoupling",
    "TorsionalModes",
    "short_circuit_torque",
    "startup_torque",
]

#: Frequencies below this fraction of the highest are rigid-body modes (a free train).
RIGID_RTOL = 1e-6
#: A node whose polar inertia is below this fraction of the largest node's has none (its
#: "mode" would be a numerical artefact at an enormous frequency): refused.
MASSLESS_RTOL = 1e-12


@dataclass(frozen=True)
class TorsionalCoupling:
    """A torsional spring (and dashpot) between nodes `i` and `j`: a flexible coupling, or a
    gear mesh already reduced to one shaft line; ``j=None`` ties node `i` to the ground.

    Examples
    --------
    >>> from duhamel.rotor import TorsionalCoupling
    >>> TorsionalCoupling(2, 3, stiffness=5e4).stiffness
    50000.0
    """

    i: int
    j: int | None = None
    _: KW_ONLY
    stiffness: float
    damping: float = 0.0

    def __post_init__(self) -> None:
        for name in ("i", "j"):
            v = getattr(self, name)
            if v is None and name == "j":
                continue
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 0:
                raise ValueError(f"`{name}` must be a node number (int >= 0), got {v!r}")
        if self.j == self.i:
            raise ValueError(f"`j` must differ from `i` (both {self.i})")
        k, c = finite_float(self.stiffness, "stiffness"), finite_float(self.damping, "damping")
        if k < 0.0 or c < 0.0:
            raise ValueError(f"`stiffness` and `damping` must be >= 0, got {k!r}, {c!r}")
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "damping", c)


@dataclass(frozen=True, eq=False)
class TorsionalModes:
    """Undamped torsional modes, ascending.

    Attributes
    ----------
    frequencies : ndarray
        Natural frequencies (rad/s) of the elastic modes.
    shapes : ndarray, shape (n_nodes, n_modes)
        Twist angle of each node, scaled so that the largest magnitude is 1 (positive).
    rigid_body : int
        Number of rigid-body modes left out (1 for a free drive train).
    """

    frequencies: NDArray[np.float64]
    shapes: NDArray[np.float64]
    rigid_body: int = 0

    @property
    def n_modes(self) -> int:
        return int(self.frequencies.size)


class Torsion:
    """The torsional model of a :class:`~duhamel.rotor.Rotor`: one twist angle per node.

    Parameters
    ----------
    rotor : Rotor
        Its shafts (torsional stiffness ``G J_p / L`` and inertia) and disks (polar
        inertia ``Ip``); its bearings carry no torque.
    couplings : sequence of TorsionalCoupling, optional
        Keyword only. Extra torsional springs and dashpots.
    zeta : float, optional
        Keyword only. Modal damping ratio of every torsional mode for transients
        (``duhamel.System(zeta=...)``); default none beyond the couplings' dashpots.

    Examples
    --------
    Two disks on a 0.5 m shaft of 40 mm diameter: the drive train's one elastic mode.

    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Disk, Rotor, Shaft, Torsion
    >>> rotor = Rotor([Shaft(0.5, 0.04, material=STEEL)],
    ...               [Disk(0, 30.0, Ip=0.4, Id=0.2), Disk(1, 10.0, Ip=0.1, Id=0.05)])
    >>> train = Torsion(rotor)
    >>> modes = train.modes()
    >>> modes.rigid_body, np.round(modes.frequencies / (2 * np.pi), 2).tolist()
    (1, [113.53])
    >>> np.round(modes.shapes[:, 0], 3).tolist()   # the disks twist against each other
    [-0.251, 1.0]
    """

    def __init__(
        self,
        rotor: object,
        *,
        couplings: Sequence[TorsionalCoupling] = (),
        zeta: float | None = None,
    ) -> None:
        shafts = getattr(rotor, "shafts", None)
        disks = getattr(rotor, "disks", None)
        if shafts is None or disks is None:
            raise TypeError(f"`rotor` must be a duhamel.rotor.Rotor, got {type(rotor).__name__}")
        self.rotor = rotor
        self.n_nodes = len(shafts) + 1
        couplings = tuple(couplings)
        for c in couplings:
            if not isinstance(c, TorsionalCoupling):
                raise TypeError(f"`couplings` must hold TorsionalCoupling, got {c!r}")
            for n in (c.i, c.j):
                if n is not None and n >= self.n_nodes:
                    raise ValueError(f"`couplings`: the rotor has no node {n}")
        self.couplings = couplings
        if zeta is not None:
            zeta = finite_float(zeta, "zeta")
            if not 0.0 <= zeta < 1.0:
                raise ValueError(f"`zeta` must be in [0, 1), got {zeta!r}")
        self.zeta = zeta
        self._J, self._K, self._C = self._assemble(shafts, disks)

    def _assemble(
        self, shafts: Sequence[object], disks: Sequence[object]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        n = self.n_nodes
        J, K, C = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
        for e, s in enumerate(shafts):
            jp = np.pi * (s.outer_diameter**4 - s.inner_diameter**4) / 32.0  # type: ignore[attr-defined]
            kt = s.material.G * jp / s.L  # type: ignore[attr-defined]
            jm = s.material.rho * jp * s.L / 6.0  # type: ignore[attr-defined]
            cell = np.ix_([e, e + 1], [e, e + 1])
            K[cell] += kt * np.array([[1.0, -1.0], [-1.0, 1.0]])
            J[cell] += jm * np.array([[2.0, 1.0], [1.0, 2.0]])
        for d in disks:
            J[d.node, d.node] += d.Ip  # type: ignore[attr-defined]
        for c in self.couplings:
            for mat, v in ((K, c.stiffness), (C, c.damping)):
                mat[c.i, c.i] += v
                if c.j is not None:
                    mat[c.j, c.j] += v
                    mat[c.i, c.j] -= v
                    mat[c.j, c.i] -= v
        inertia = np.diag(J)
        light = np.flatnonzero(inertia <= MASSLESS_RTOL * float(inertia.max(initial=0.0)))
        if light.size or not np.any(inertia > 0.0):
            bad = int(light[0]) if light.size else 0
            raise ValueError(
                f"node {bad} has no polar inertia (a massless shaft and no disk there: "
                f"{inertia[bad]:.3g} kg m^2): give it a Disk with `Ip` > 0"
            )
        return J, K, C

    # ------------------------------------------------------------------ layout
    @property
    def n_dof(self) -> int:
        """One twist angle per node."""
        return self.n_nodes

    @property
    def dof_labels(self) -> tuple[str, ...]:
        """``theta_0, theta_1, ...``."""
        return tuple(f"theta_{k}" for k in range(self.n_nodes))

    def dof(self, node: int) -> int:
        """The dof of `node`'s twist angle (for loads and results)."""
        if isinstance(node, bool) or not isinstance(node, int | np.integer):
            raise TypeError(f"`node` must be a node number, got {node!r}")
        if not 0 <= node < self.n_nodes:
            raise ValueError(f"`node` must be in [0, {self.n_nodes}), got {node}")
        return int(node)

    def matrices(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``(J, K_t, C_t)``: polar inertia, torsional stiffness, couplings' damping."""
        return self._J.copy(), self._K.copy(), self._C.copy()

    # ------------------------------------------------------------------ analyses
    def modes(self, n: int | None = None) -> TorsionalModes:
        """Undamped torsional modes (``K_t u = omega^2 J u``, symmetric eigensolver), the
        lowest `n` elastic ones (all by default); rigid-body modes counted apart."""
        import scipy.linalg

        lam, vec = scipy.linalg.eigh(self._K, self._J)
        omega = np.sqrt(np.clip(lam, 0.0, None))
        top = float(omega.max()) if omega.size else 0.0
        elastic = omega > RIGID_RTOL * top
        omega, vec = omega[elastic], vec[:, elastic]
        if n is not None:
            if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
                raise ValueError(f"`n` must be a positive integer, got {n!r}")
            omega, vec = omega[:n], vec[:, :n]
        big = np.argmax(np.abs(vec), axis=0)
        vec = vec / vec[big, np.arange(vec.shape[1])]
        return TorsionalModes(omega, vec, int(np.count_nonzero(~elastic)))

    def natural_frequencies(self, n: int | None = None) -> NDArray[np.float64]:
        """Torsional natural frequencies (rad/s, ascending): :meth:`modes`' frequencies."""
        return self.modes(n).frequencies

    def campbell(self, speeds: ArrayLike, n_modes: int | None = None) -> Campbell:
        """The torsional Campbell diagram: the natural frequencies at each of `speeds`
        (horizontal lines: the linear torsional model does not depend on the spin),
        whirl ``"torsional"``; plot with :func:`duhamel.rotor.plot_campbell`, read its
        critical speeds with :meth:`critical_speeds`."""
        ws = as_float_array(speeds, "speeds", ndim=1)
        f = self.natural_frequencies(n_modes)
        freq = np.tile(f, (ws.size, 1))
        return Campbell(ws, freq, np.zeros_like(freq), np.full(freq.shape, "torsional"),
                        mac=np.ones_like(freq), tracked=True)  # fmt: skip

    def critical_speeds(
        self, orders: Sequence[float] = (1.0, 2.0), speed_range: tuple[float, float] | None = None
    ) -> list[tuple[float, float, int]]:
        """Where the excitation ``order x speed`` meets a torsional natural frequency:
        ``(speed, order, mode)`` with ``speed = omega_mode / order`` (rad/s), ascending,
        those within `speed_range` when given."""
        out = []
        for order in orders:
            h = positive_float(order, "orders")
            for k, f in enumerate(self.natural_frequencies()):
                out.append((float(f) / h, h, k))
        if speed_range is not None:
            lo, hi = (finite_float(v, "speed_range") for v in speed_range)
            out = [c for c in out if lo <= c[0] <= hi]
        return sorted(out)

    def system(self) -> object:
        """A :class:`duhamel.System` on the twist angles (``M = J``, ``K = K_t``, the
        couplings' dashpots and `zeta`), for torque transients through ``duhamel.solve``."""
        import duhamel

        if self.zeta is None:
            c = self._C if np.any(self._C) else None
            return duhamel.System(self._J, self._K, c)
        if np.any(self._C):
            raise ValueError("give `zeta` or couplings with `damping`, not both")
        zeta = np.full(self.n_dof, self.zeta)
        return duhamel.System(self._J, self._K, zeta=zeta)


def startup_torque(
    dof: int,
    *,
    t: ArrayLike,
    average: float,
    pulsating: float,
    line_frequency: float,
    run_up_time: float,
) -> object:
    """A synchronous motor's start-up air-gap torque as a ``duhamel.loads.Tabulated`` load.

    During an asynchronous start the slip ``s(t) = 1 - t / run_up_time`` falls from 1 to 0;
    the torque is the average accelerating torque plus a pulsation at twice the slip
    frequency, ``T(t) = average + pulsating sin(phi(t))`` with ``phi' = 2 pi 2 f s(t)``
    (``f`` the line frequency), so ``phi = 4 pi f (t - t^2 / (2 run_up_time))``: the
    pulsation sweeps from ``2 f`` down to zero and crosses every torsional mode below it,
    which is what the transient torsional analysis of API 617 looks at. After
    `run_up_time` the torque is held at `average` + the pulsation's last value.

    Parameters
    ----------
    dof : int
        The motor's twist dof (:meth:`Torsion.dof`).
    t : array_like
        Sample times (s), ascending: fine enough for the pulsation (20 or more samples per
        period of ``2 f``); the load is linear between them.
    average, pulsating : float
        Keyword only. Average and pulsating torque amplitudes (N m).
    line_frequency : float
        Keyword only. ``f`` (Hz).
    run_up_time : float
        Keyword only. Time (s) from standstill to synchronous speed.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.torsion import startup_torque
    >>> load = startup_torque(0, t=np.linspace(0, 1, 4001), average=1e3, pulsating=5e2,
    ...                       line_frequency=50.0, run_up_time=1.0)
    >>> round(float(load.values[0]), 6), round(float(load.values[-1]), 6)
    (1000.0, 1000.0)
    """
    import duhamel

    ts = as_float_array(t, "t", ndim=1)
    T0, Tp = finite_float(average, "average"), finite_float(pulsating, "pulsating")
    f = positive_float(line_frequency, "line_frequency")
    tr = positive_float(run_up_time, "run_up_time")
    tau = np.minimum(ts, tr)
    phi = 4.0 * np.pi * f * (tau - tau**2 / (2.0 * tr))
    return duhamel.loads.Tabulated(dof, t=ts, values=T0 + Tp * np.sin(phi), hold=True)


def short_circuit_torque(
    dof: int,
    *,
    t: ArrayLike,
    amplitudes: tuple[float, float],
    line_frequency: float,
    time_constant: float,
    t0: float = 0.0,
) -> object:
    """A short-circuit air-gap torque as a ``duhamel.loads.Tabulated`` load.

    ``T(t) = e^{-(t - t0) / tau} (T_1 sin(omega (t - t0)) + T_2 sin(2 omega (t - t0)))``
    from the fault at `t0` on, ``omega = 2 pi f``: the decaying line-frequency and
    twice-line-frequency components of a terminal short circuit (a three-phase fault is
    mostly ``T_1``; a line-to-line fault adds ``T_2``); zero before `t0`.

    Parameters
    ----------
    dof : int
        The machine's twist dof (:meth:`Torsion.dof`).
    t : array_like
        Sample times (s), ascending (20 or more per period of ``2 f``).
    amplitudes : (float, float)
        Keyword only. ``(T_1, T_2)`` (N m).
    line_frequency : float
        Keyword only. ``f`` (Hz).
    time_constant : float
        Keyword only. ``tau`` (s), the decay of the transient currents.
    t0 : float
        Keyword only. Time of the fault (s).

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.torsion import short_circuit_torque
    >>> load = short_circuit_torque(1, t=np.linspace(0, 0.2, 2001), amplitudes=(4e3, -2e3),
    ...                             line_frequency=50.0, time_constant=0.1)
    >>> bool(abs(load.values).max() < 6e3), float(load.values[0])
    (True, 0.0)
    """
    import duhamel

    ts = as_float_array(t, "t", ndim=1)
    try:
        T1, T2 = (finite_float(a, "amplitudes") for a in amplitudes)
    except (TypeError, ValueError):
        raise ValueError(
            f"`amplitudes` must be two torques (T_1, T_2), got {amplitudes!r}"
        ) from None
    w = 2.0 * np.pi * positive_float(line_frequency, "line_frequency")
    tau = positive_float(time_constant, "time_constant")
    s = np.clip(ts - finite_float(t0, "t0"), 0.0, None)
    values = np.exp(-s / tau) * (T1 * np.sin(w * s) + T2 * np.sin(2.0 * w * s))
    return duhamel.loads.Tabulated(dof, t=ts, values=values)
