"""A rotor's linear analyses with active magnetic bearings (:class:`MagneticBearing` among
its bearings): the closed loop's modes and the bearings' dynamic stiffness in the frequency
domain.

Each bearing axis (dof ``j``) pushes with ``f = k_s x_j - k_i C(s) x_j`` (the controller
``C(s)`` from the measured displacement to the current, its states ``z' = A_c z + B_c x_j``,
``C(s) x_j = C_c z + D_c x_j``):

* **Modes** are those of the closed loop, the rotor's state and every controller state
  together, from the pencil (scaled as :func:`duhamel.rotor.modes.complex_modes`)

      [[I, 0, 0], [0, M, 0], [0, 0, I]] s' = [[0, sigma I, 0],
                                              [-(K + K_d)/sigma, -D, -F],
                                              [B/sigma, 0, A_c]] s,

  ``s = (sigma x, x', z)``, ``K_d`` the direct feedback ``(k_i D_c - k_s)`` at the axes,
  ``F`` the force of the controller states ``k_i C_c``, ``B`` their input ``B_c``: exact,
  the controller's own poles included (real ones, a derivative filter's, are listed with
  the overdamped eigenvalues).
* **Harmonic responses** at the excitation frequency ``w`` need only the bearings' dynamic
  stiffness ``d(w) = k_i C(i w) - k_s`` on each axis, added to ``K`` as ``Re d`` and to
  ``C`` as ``Im d / w`` — ROSS's frequency-domain law (``k_eq + i w c_eq = k_s + k_i k_amp
  k_sense C(i w)`` in ROSS's signs, its ``k_s < 0``), exactly the steady state of the closed
  loop at ``w``: the unbalance response (``w`` the speed) and the receptances cost what the
  conventional rotor's do.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.modes import Modes, modes_of, split_eigenvalues

__all__ = [
    "amb_axes",
    "dynamic_stiffness",
    "loop_frequency_response",
    "loop_modes",
    "stacked",
    "with_bearings_at",
]

Axes = Sequence[tuple[int, Any]]


def amb_axes(bearings: Sequence[Any], dof: Callable[[int, str], int]) -> list[tuple[int, Any]]:
    """Each magnetic bearing's two axes: ``(dof, bearing)`` for x and y."""
    out = []
    for b in bearings:
        out += [(int(dof(b.node, "x")), b), (int(dof(b.node, "y")), b)]
    return out


def dynamic_stiffness(axes: Axes, n: int, w: float) -> tuple[NDArray, NDArray]:
    """The bearings' ``d(w) = k_i C(i w) - k_s`` at excitation frequency `w` (rad/s) as
    diagonal stiffness and damping terms ``(Re d, Im d / w)`` over the `n` dofs."""
    k, c = np.zeros(n), np.zeros(n)
    for j, b in axes:
        value = complex(b.k_i * b.controller(1j * w) - b.k_s)
        if not np.isfinite(value):
            raise ValueError(
                f"the magnetic bearing at node {b.node}: its controller is infinite at "
                f"{w:g} rad/s (an integrator at zero frequency): no harmonic response there"
            )
        k[j] += value.real
        if value.imag != 0.0:
            c[j] += value.imag / w
    return k, c


def with_bearings_at(matrices: Callable[[float], Any], axes: Axes) -> Callable[[float], Any]:
    """``speed -> (M, K, C, G)`` with the bearings' dynamic stiffness at the excitation
    frequency equal to the speed (an unbalance response's, a synchronous receptance's)."""

    def at(w: float) -> RotorMatrices:
        M, K, C, G = matrices(w)
        k, c = dynamic_stiffness(axes, np.shape(M)[0], float(w))
        return RotorMatrices(M, K + np.diag(k), C + np.diag(c), G)

    return at


def loop_frequency_response(
    mats: Any,
    axes: Axes,
    speed: float,
    frequencies: Any,
    inputs: Sequence[int],
    outputs: Sequence[int],
    *,
    labels: Sequence[str],
) -> Any:
    """Receptances at spin `speed` with the bearings' dynamic stiffness at each excitation
    frequency: :func:`duhamel.rotor.frequency.frequency_response` per frequency."""
    from duhamel._engine.validate import as_float_array
    from duhamel.rotor.frequency import FrequencyResponse, frequency_response

    ws = as_float_array(frequencies, "frequencies", ndim=1)
    if ws.size == 0:
        raise ValueError("`frequencies` is empty")
    M, K, C, G = (np.asarray(a, dtype=float) for a in mats)
    parts = []
    for w in ws:
        k, c = dynamic_stiffness(axes, M.shape[0], float(w))
        at = RotorMatrices(M, K + np.diag(k), C + np.diag(c), G)
        parts.append(frequency_response(at, speed, [w], inputs, outputs).response[0])
    return FrequencyResponse(
        float(speed), ws, np.stack(parts), tuple(inputs), tuple(outputs), tuple(labels)
    )


def stacked(speeds: Any, parts: Sequence[Any]) -> Any:
    """The :class:`FrequencyResponseMap` of the responses `parts` at `speeds`."""
    from duhamel.rotor.frequency import FrequencyResponseMap

    if not parts:
        raise ValueError("`speeds` is empty")
    first = parts[0]
    return FrequencyResponseMap(
        np.asarray([p.speed for p in parts], dtype=float),
        first.frequencies,
        np.stack([p.response for p in parts]),
        first.inputs,
        first.outputs,
        first.labels,
    )


def loop_modes(
    M: NDArray[np.float64],
    D: NDArray[np.float64],
    K: NDArray[np.float64],
    axes: Axes,
    *,
    speed: float,
    n: int | None,
    length_scale: float,
    layout: Any = None,
) -> Modes:
    """The closed loop's modes (see the module docstring): the rotor ``(M, D = C + speed G,
    K)`` with the magnetic bearings' `axes`, the lowest `n` (`layout`: the dofs per node,
    :func:`duhamel.rotor.modes.complex_modes`)."""
    import scipy.linalg

    A, E, scale = loop_pencil(M, D, K, axes)
    lam, vec = scipy.linalg.eig(A, E, check_finite=False)
    nd = M.shape[0]
    lam_o, shapes, over = split_eigenvalues(lam, vec[:nd] / scale)
    return modes_of(lam_o, shapes, over, speed=speed, n=n, length_scale=length_scale, layout=layout)


def loop_pencil(
    M: NDArray[np.float64], D: NDArray[np.float64], K: NDArray[np.float64], axes: Axes
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """``(A, E, sigma)`` of the closed loop's pencil ``E s' = A s``, ``s = (sigma x, x',
    z)``."""
    nd = M.shape[0]
    blocks = [b.controller.state_space() for _, b in axes]
    nz = int(sum(a.shape[0] for a, _, _, _ in blocks))
    Kd = np.array(K, dtype=float)
    kmax, mmax = float(np.max(np.abs(np.diag(K)))), float(np.max(np.diag(M)))
    scale = np.sqrt(kmax / mmax) if kmax > 0.0 and mmax > 0.0 else 1.0
    N = 2 * nd + nz
    A = np.zeros((N, N))
    E = np.zeros((N, N))
    E[:nd, :nd] = np.eye(nd)
    E[nd : 2 * nd, nd : 2 * nd] = M
    E[2 * nd :, 2 * nd :] = np.eye(nz)
    A[:nd, nd : 2 * nd] = scale * np.eye(nd)
    A[nd : 2 * nd, nd : 2 * nd] = -D
    row = 2 * nd
    for (j, b), (Ac, Bc, Cc, Dc) in zip(axes, blocks, strict=True):
        size = Ac.shape[0]
        z = slice(row, row + size)
        Kd[j, j] += b.k_i * Dc - b.k_s
        A[nd + j, z] = -b.k_i * Cc
        A[z, j] = Bc / scale
        A[z, z] = Ac
        row += size
    A[nd : 2 * nd, :nd] = -Kd / scale
    return A, E, scale
