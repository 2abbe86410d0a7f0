"""A rotor's matrices as a :class:`duhamel.System` for time integration (constant speed or a
run-up): the symmetric background, the gyroscopic and skew-symmetric bearing couplings, the
rotor loads.

Shared by :meth:`duhamel.rotor.Rotor.system` and :func:`duhamel.rotor.from_ross`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._core import Element
from duhamel.couplings import LinearCoupling
from duhamel.loads import Load
from duhamel.rotor._protocols import RotorModel
from duhamel.rotor.bearing import Bearing
from duhamel.rotor.loads import RotorLoad
from duhamel.speed import SpeedLaw
from duhamel.system import System

__all__ = [
    "add_couplings",
    "add_rotor_loads",
    "background",
    "bearing_elements",
    "nonzero",
    "storage",
]


def nonzero(a: NDArray[np.float64]) -> bool:
    """Whether any entry of `a` is nonzero."""
    return bool(np.any(a != 0.0))


def storage(sparse: bool) -> Callable[[Any], Any]:
    """How the System stores its matrices: ``scipy.sparse.csr_array`` or as given.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.transient import storage
    >>> type(storage(True)(np.eye(2))).__name__, type(storage(False)(np.eye(2))).__name__
    ('csr_array', 'ndarray')
    """
    if not sparse:
        return lambda a: a
    import scipy.sparse as sp

    return sp.csr_array


def background(
    M: NDArray[np.float64],
    k_sym: NDArray[np.float64],
    c_sym: NDArray[np.float64],
    structural: Callable[[], NDArray[np.float64]],
    *,
    zeta: float | NDArray[np.float64] | None,
    rayleigh: tuple[float, float] | None,
    conv: Callable[[Any], Any],
) -> System:
    """The System of the symmetric background ``(M, K_sym)`` and its damping.

    With (symmetric) bearing damping `c_sym`, ``C = structural() + c_sym`` as a matrix;
    otherwise the rotor's `rayleigh` or `zeta` as given (or none).

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.transient import background
    >>> background(np.eye(2), np.eye(2), np.zeros((2, 2)), lambda: np.zeros((2, 2)),
    ...            zeta=0.02, rayleigh=None, conv=lambda a: a)
    System(n_dof=2, damping='zeta', loads=0)
    """
    if nonzero(c_sym):
        return System(conv(M), conv(k_sym), conv(structural() + c_sym))
    if rayleigh is not None:
        return System(conv(M), conv(k_sym), rayleigh=rayleigh)
    if zeta is not None:
        return System(conv(M), conv(k_sym), zeta=zeta)
    return System(conv(M), conv(k_sym))


def bearing_elements(
    bearings: Iterable[Bearing],
    dof: Callable[[int, str], int],
    static_deflection: Callable[[], NDArray[np.float64]],
    speed: float,
) -> list[Element]:
    """The bearings' nonlinear parts as :mod:`duhamel.elements` on the global dofs `dof`
    gives; a cubic law without its own ``x_stat`` takes the magnitude of the bearing's
    vertical deflection in `static_deflection()` (computed once, when needed).

    Examples
    --------
    >>> from duhamel.rotor import Bearing
    >>> from duhamel.rotor.transient import bearing_elements
    >>> b = Bearing(1, 1e6, 1e6, contact=(1e-4, 1e8))
    >>> dof = lambda n, d: 4 * n + (d == "y")
    >>> [type(e).__name__ for e in bearing_elements([b], dof, None, 0.0)]
    ['Contact']
    """
    out: list[Element] = []
    static: NDArray[np.float64] | None = None
    for b in bearings:
        dx, dy = dof(b.node, "x"), dof(b.node, "y")
        x_stat = b.x_stat
        if b.beta != 0.0 and x_stat is None:
            if static is None:
                static = static_deflection()
            x_stat = abs(float(static[dy]))
            if x_stat == 0.0:
                raise ValueError(
                    f"the bearing at node {b.node} does not deflect under the weight; "
                    "give its cubic law an `x_stat`"
                )
        out.extend(b.elements(dx, dy, x_stat, speed=speed))
    return out


def add_couplings(
    system: System,
    G: NDArray[np.float64],
    speed: float | SpeedLaw,
    k_skew: NDArray[np.float64],
    c_skew: NDArray[np.float64],
    conv: Callable[[Any], Any],
    magnetic: Iterable[Any] = (),
    dof: Callable[[int, str], int] | None = None,
) -> None:
    """Add the gyroscopic coupling, the skew-symmetric bearing parts and the magnetic
    bearings' closed loops to `system`.

    ``LinearCoupling(C=speed G)`` at a constant speed (omitted when zero),
    ``LinearCoupling(C=G, scale=law)`` along a varying speed law,
    ``LinearCoupling(K=k_skew, C=c_skew)`` (omitted when both are zero), and the
    :class:`~duhamel.rotor.MagneticBearing` s of `magnetic` (dofs from `dof`) as one
    :class:`duhamel.feedback.Feedback` with their controllers' states.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.rotor.transient import add_couplings
    >>> system = duhamel.System(np.eye(2), np.eye(2))
    >>> G = np.array([[0.0, 1.0], [-1.0, 0.0]])
    >>> add_couplings(system, G, 10.0, np.zeros((2, 2)), np.zeros((2, 2)), lambda a: a)
    >>> system.couplings[0].C.tolist()
    [[0.0, 10.0], [-10.0, 0.0]]
    """
    bearings = tuple(magnetic)
    if isinstance(speed, SpeedLaw) and bearings and nonzero(G):
        # the controllers' states need the exact first-order route, whose couplings are
        # constant: omega0 G there, the change along the law as an element
        w0 = float(np.asarray(speed.omega(np.array([0.0])))[0])
        if w0 != 0.0:
            system.add(LinearCoupling(C=conv(w0 * G)))
        system.add(gyroscopic_change(np.asarray(G, dtype=float), speed, w0))
    elif isinstance(speed, SpeedLaw):  # a run-up: the engine scales G by omega(t)
        if nonzero(G):
            system.add(LinearCoupling(C=conv(G), scale=speed))
    elif nonzero(speed * G):
        system.add(LinearCoupling(C=conv(speed * G)))
    if nonzero(k_skew) or nonzero(c_skew):
        system.add(
            LinearCoupling(
                K=conv(k_skew) if nonzero(k_skew) else None,
                C=conv(c_skew) if nonzero(c_skew) else None,
            )
        )
    if bearings:
        from duhamel.rotor.magnetic import feedback

        assert dof is not None
        system.add(feedback(bearings, dof, system.n_dof))


def gyroscopic_change(G: NDArray[np.float64], law: SpeedLaw, w0: float) -> Element:
    """``(omega(t) - w0) G x'`` along the speed law `law` as a
    :class:`duhamel.elements.Callable` on the dofs `G` couples (with its exact tangent): the
    part of a run-up's gyroscopic force beyond the constant ``w0 G`` that a background with
    feedback states carries (a Python element: such a run cannot be stored).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.rotor.transient import gyroscopic_change
    >>> G = np.array([[0.0, 0.5, 0.0], [-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]])
    >>> e = gyroscopic_change(G, duhamel.speed.LinearRunUp(100.0, 300.0, 1.0), 100.0)
    >>> e.dofs, e.fn(np.zeros(2), np.array([1.0, 0.0]), 0.5).tolist()
    ((0, 1), [0.0, -50.0])
    """
    from duhamel.elements import Callable as CallableElement

    dofs = np.flatnonzero(np.any(G != 0.0, axis=0) | np.any(G != 0.0, axis=1))
    Gs = np.ascontiguousarray(G[np.ix_(dofs, dofs)])
    zero = np.zeros_like(Gs)

    def factor(t: float) -> float:
        return float(np.asarray(law.omega(np.array([t])))[0]) - w0

    def force(x: NDArray, v: NDArray, t: float) -> NDArray:
        return factor(t) * (Gs @ v)

    def jacobian(x: NDArray, v: NDArray, t: float) -> tuple[NDArray, NDArray]:
        return zero, factor(t) * Gs

    return CallableElement(dofs.tolist(), force, jacobian=jacobian)


def add_rotor_loads(
    system: System, rotor: RotorModel, loads: Iterable[RotorLoad | Load], speed: Any
) -> None:
    """Add `loads` to `system`: rotor loads expanded on `rotor` at `speed`, plain
    :mod:`duhamel.loads` as they are.

    Examples
    --------
    >>> import duhamel
    >>> from duhamel.rotor import STEEL, Rotor, Shaft, SuddenForce
    >>> from duhamel.rotor.transient import add_rotor_loads
    >>> rotor = Rotor([Shaft(1.0, 0.05, material=STEEL)])
    >>> system = duhamel.System(rotor.matrices().M, rotor.matrices().M)
    >>> add_rotor_loads(system, rotor, [SuddenForce(1, fy=-5.0)], 0.0)
    >>> system.loads[0].dof
    5
    """
    for load in loads:
        if isinstance(load, RotorLoad):
            for part in load.loads(rotor, speed):
                system.add_load(part)
        elif isinstance(load, Load):
            system.add_load(load)
        else:
            raise TypeError(
                "`loads` must contain duhamel.rotor loads (Unbalance, Gravity, "
                f"SuddenForce) or duhamel.loads loads, got {type(load).__name__}"
            )
