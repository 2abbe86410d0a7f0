"""Frequency response functions (receptances) of a rotor at a constant spin speed.

``H(w)`` solves ``(K - w^2 M + i w (C + Omega G)) H = B`` (``B`` the unit forces of the
inputs), so that a force ``Re(F e^{i w t})`` on an input gives ``x = Re(H F e^{i w t})`` at the
outputs: the ``e^{i w t}`` convention of :func:`duhamel.rotor.unbalance_response`. The
frequency ``w`` and the spin speed ``Omega`` are independent (the bearing coefficients are
those of the spin speed); ``speed="synchronous"`` sets ``Omega = w`` at each frequency, as
ROSS's ``run_freq_response`` does.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float
from duhamel.rotor._banded import bandwidths, refined_banded_solves, worth_banding

__all__ = ["FrequencyResponse", "FrequencyResponseMap", "frequency_response", "resolve_dofs"]

#: Frequencies solved per batched dense call (bounds the memory of the stacked matrices).
_BATCH = 64

#: A dof given as its index, its label (``"x_2"``) or ``(node, direction)``.
DofSpec = int | str | tuple[int, str]


def resolve_dofs(
    items: Sequence[DofSpec] | DofSpec,
    name: str,
    *,
    n_dof: int,
    labels: Sequence[str],
    dof: Callable[[int, str], int],
) -> tuple[int, ...]:
    """Global dof indices of `items` (indices, labels or ``(node, direction)`` pairs)."""
    if isinstance(items, str | int | np.integer) or (
        isinstance(items, tuple) and len(items) == 2 and isinstance(items[1], str)
    ):
        items = [items]  # type: ignore[list-item]
    out = []
    for item in items:  # type: ignore[union-attr]
        if isinstance(item, bool):
            raise TypeError(f"`{name}`: a dof must be an index, label or (node, direction)")
        if isinstance(item, int | np.integer):
            if not 0 <= int(item) < n_dof:
                raise ValueError(f"`{name}`: dof {int(item)} is not in [0, {n_dof - 1}]")
            out.append(int(item))
        elif isinstance(item, str):
            if item not in labels:
                raise ValueError(
                    f"`{name}`: no dof is labelled {item!r} (labels like {labels[0]!r})"
                )
            out.append(list(labels).index(item))
        elif isinstance(item, tuple) and len(item) == 2:
            out.append(int(dof(item[0], item[1])))
        else:
            raise TypeError(
                f"`{name}`: a dof must be an index, a label or (node, direction), got {item!r}"
            )
    if not out:
        raise ValueError(f"`{name}` is empty")
    return tuple(out)


@dataclass(frozen=True, eq=False)
class FrequencyResponse:
    """Receptances at one spin speed: ``x_out = Re(response[k, o, i] F_i e^{i w_k t})``.

    Attributes
    ----------
    speed : float or str
        Spin speed (rad/s), or ``"synchronous"`` (the spin speed equals each frequency).
    frequencies : ndarray, shape (n_frequencies,)
        rad/s.
    response : ndarray of complex, shape (n_frequencies, n_outputs, n_inputs)
        Receptances (m/N, rad/N, m/(N m), rad/(N m)).
    inputs, outputs : tuple of int
        Global dofs of the inputs and the outputs.
    labels : tuple of str
        The model's dof labels.
    """

    speed: float | str
    frequencies: NDArray[np.float64]
    response: NDArray[np.complex128]
    inputs: tuple[int, ...]
    outputs: tuple[int, ...]
    labels: tuple[str, ...]

    def _pick(self, output: int, input: int) -> NDArray[np.complex128]:
        return self.response[:, int(output), int(input)]

    def magnitude(self, output: int = 0, input: int = 0) -> NDArray[np.float64]:
        """``|H|`` of the `output`-th output to the `input`-th input (positions, not dofs)."""
        return np.abs(self._pick(output, input))

    def phase(self, output: int = 0, input: int = 0) -> NDArray[np.float64]:
        """``angle(H)`` (rad) of the `output`-th output to the `input`-th input."""
        return np.angle(self._pick(output, input))

    def plot_bode(self, output: int = 0, input: int = 0, **kwargs: Any) -> Any:
        """Magnitude (log) and phase against frequency; returns the two Axes."""
        from duhamel.rotor._plot_frequency import plot_frf_bode

        return plot_frf_bode(self, output, input, **kwargs)

    def plot_nyquist(self, output: int = 0, input: int = 0, **kwargs: Any) -> Any:
        """``Re(H)`` against ``Im(H)`` over the frequencies; returns the Axes."""
        from duhamel.rotor._plot_frequency import plot_frf_nyquist

        return plot_frf_nyquist(self, output, input, **kwargs)


@dataclass(frozen=True, eq=False)
class FrequencyResponseMap:
    """Receptances over spin speeds and frequencies.

    Attributes
    ----------
    speeds : ndarray, shape (n_speeds,)
        rad/s.
    frequencies : ndarray, shape (n_frequencies,)
        rad/s.
    response : ndarray of complex, shape (n_speeds, n_frequencies, n_outputs, n_inputs)
    inputs, outputs, labels
        As :class:`FrequencyResponse`.
    """

    speeds: NDArray[np.float64]
    frequencies: NDArray[np.float64]
    response: NDArray[np.complex128]
    inputs: tuple[int, ...]
    outputs: tuple[int, ...]
    labels: tuple[str, ...]

    def at(self, k: int) -> FrequencyResponse:
        """The response at the `k`-th speed."""
        return FrequencyResponse(
            float(self.speeds[k]),
            self.frequencies,
            self.response[k],
            self.inputs,
            self.outputs,
            self.labels,
        )

    def plot_map(self, output: int = 0, input: int = 0, **kwargs: Any) -> Any:
        """``log10 |H|`` over speed (x) and frequency (y) with the 1x line; returns the Axes."""
        from duhamel.rotor._plot_frequency import plot_frf_map

        return plot_frf_map(self, output, input, **kwargs)


def _solve(
    mats: tuple,
    ws: NDArray[np.float64],
    spins: NDArray[np.float64],
    B: NDArray[np.complex128],
) -> NDArray[np.complex128]:
    """``(K - w^2 M + i w (C + Omega G))^-1 B`` per frequency: banded LU for large banded
    models (as the unbalance response), batched dense LU otherwise; either with one step of
    iterative refinement, its residual in extended precision, so that the receptances are
    those of the (rounded) dynamic stiffness to about round-off even near resonances, where
    its condition number reaches 1e7."""
    M, K, C, G = mats
    n = M.shape[0]
    band = bandwidths(mats)
    if worth_banding(n, *band):
        out = refined_banded_solves(mats, ws, spins, B, *band)
    else:
        out = np.empty((ws.size, n, B.shape[1]), dtype=complex)
        Bl = B.astype(np.clongdouble)
        for start in range(0, ws.size, _BATCH):
            w = ws[start : start + _BATCH, None, None]
            spin = spins[start : start + _BATCH, None, None]
            A = K[None] - w**2 * M[None] + 1j * w * (C[None] + spin * G[None])
            try:
                x = np.linalg.solve(A, B[None])
                res = Bl - A.astype(np.clongdouble) @ x.astype(np.clongdouble)
                out[start : start + _BATCH] = x + np.linalg.solve(A, res.astype(complex))
            except np.linalg.LinAlgError:
                raise ValueError(
                    f"the dynamic stiffness is singular at a frequency in [{ws[0]:g}, "
                    f"{ws[-1]:g}] rad/s (an undamped resonance, or a rigid-body mode at zero "
                    "frequency): add damping or move the frequencies off it"
                ) from None
    if not np.all(np.isfinite(out)):
        raise ValueError("the frequency response is not finite (an undamped resonance?)")
    return out


def frequency_response(
    matrices: Any,
    speed: float | str,
    frequencies: ArrayLike,
    inputs: Sequence[int],
    outputs: Sequence[int],
    *,
    labels: Sequence[str] = (),
) -> FrequencyResponse:
    """Receptances between dofs `inputs` and `outputs` at spin `speed` (rad/s, or
    ``"synchronous"``), one complex solve per frequency.

    Parameters
    ----------
    matrices : RotorMatrices or callable
        ``(M, K, C, G)``, or ``speed -> (M, K, C, G)`` (coefficients that depend on the spin).
    speed : float or "synchronous"
        Spin speed (rad/s); ``"synchronous"``: the spin speed equals each frequency.
    frequencies : array_like
        Excitation frequencies (rad/s).
    inputs, outputs : sequence of int
        Global dofs (already resolved, see :func:`resolve_dofs`).
    labels : sequence of str
        Keyword only. The model's dof labels (kept on the result).

    Returns
    -------
    FrequencyResponse

    Examples
    --------
    A 1-dof oscillator (the second dof pair is a dummy): ``H = 1 / (k - w^2 m + i w c)``.

    >>> import numpy as np
    >>> from duhamel.rotor.assembly import RotorMatrices
    >>> from duhamel.rotor.frequency import frequency_response
    >>> I, Z = np.eye(2), np.zeros((2, 2))
    >>> mats = RotorMatrices(2.0 * I, 800.0 * I, 4.0 * I, Z)
    >>> frf = frequency_response(mats, 0.0, [10.0, 20.0], [0], [0])
    >>> bool(np.allclose(frf.response[:, 0, 0], 1 / (800 - 2 * np.array([100, 400]) + 40j * np.array([1, 2]))))
    True
    """  # noqa: E501
    ws = as_float_array(frequencies, "frequencies", ndim=1)
    if ws.size == 0:
        raise ValueError("`frequencies` is empty")
    synchronous = isinstance(speed, str)
    if synchronous and speed != "synchronous":
        raise ValueError(f"`speed` must be a number or 'synchronous', got {speed!r}")
    fixed = None if callable(matrices) else tuple(np.asarray(a, dtype=float) for a in matrices)
    first = fixed if fixed is not None else None
    if first is None and not synchronous:
        first = tuple(np.asarray(a, dtype=float) for a in matrices(finite_float(speed, "speed")))
    n = (first[0] if first is not None else np.asarray(matrices(float(ws[0]))[0])).shape[0]
    B = np.zeros((n, len(inputs)), dtype=complex)
    B[list(inputs), np.arange(len(inputs))] = 1.0
    if synchronous:
        out = np.empty((ws.size, n, len(inputs)), dtype=complex)
        for k, w in enumerate(ws):
            at = first if first is not None else tuple(np.asarray(a) for a in matrices(float(w)))
            out[k] = _solve(at, ws[k : k + 1], ws[k : k + 1], B)[0]
    else:
        spin = finite_float(speed, "speed")
        out = _solve(first, ws, np.full(ws.size, spin), B)  # type: ignore[arg-type]
    response = out[:, list(outputs), :]
    return FrequencyResponse(
        speed if synchronous else float(speed),
        ws,
        response,
        tuple(inputs),
        tuple(outputs),
        tuple(labels),
    )


def frequency_response_map(
    matrices: Any,
    speeds: ArrayLike,
    frequencies: ArrayLike,
    inputs: Sequence[int],
    outputs: Sequence[int],
    *,
    labels: Sequence[str] = (),
) -> FrequencyResponseMap:
    """:func:`frequency_response` at each of `speeds` (rad/s): a speed-frequency map."""
    ss = as_float_array(speeds, "speeds", ndim=1)
    if ss.size == 0:
        raise ValueError("`speeds` is empty")
    parts = [
        frequency_response(matrices, float(s), frequencies, inputs, outputs, labels=labels)
        for s in ss
    ]
    return FrequencyResponseMap(
        ss,
        parts[0].frequencies,
        np.stack([p.response for p in parts]),
        tuple(inputs),
        tuple(outputs),
        tuple(labels),
    )
