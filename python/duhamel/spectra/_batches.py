"""The Rust spectra loops called on batches of periods, so that a long computation answers
Ctrl-C between batches (Python handles a pending signal as soon as a call returns) and a
batch stays short whatever the records: about :data:`BATCH_WORK` oscillator-samples per
worker thread (measured: 0.1 s for the elastic spectra on one core)."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator

import numpy as np
from numpy.typing import NDArray

from duhamel import _core

__all__ = ["BATCH_WORK", "ductility", "elastic", "rotd_peaks"]

#: Oscillator-samples per worker thread and batch.
BATCH_WORK = 2e7


def _slices(n: int, work_per_period: float, threads: int | None) -> Iterator[slice]:
    """Consecutive slices of `n` periods, each about BATCH_WORK per thread."""
    workers = threads if threads is not None else (os.cpu_count() or 1)
    size = max(1, int(BATCH_WORK * workers // max(1.0, work_per_period)))
    for start in range(0, n, size):
        yield slice(start, min(n, start + size))


def _batched(
    n: int, work: float, threads: int | None, run: Callable[[slice], NDArray], axis: int
) -> NDArray:
    return np.concatenate([run(s) for s in _slices(n, work, threads)], axis=axis)


def elastic(
    records: list[NDArray],
    dts: list[float],
    p: NDArray,
    z: NDArray,
    threads: int | None,
    *,
    exact: bool = False,
) -> tuple[NDArray, NDArray, NDArray]:
    """``(sd, sv, sa)`` of shape (records, dampings, periods); `exact`: the true peaks
    between the samples too."""
    work = float(sum(a.size for a in records) * z.size)

    def run(s: slice) -> NDArray:
        sd, sv, sa = _core.elastic_spectra(records, dts, p[s], z, threads, exact)
        shape = (len(records), z.size, len(p[s]))
        return np.stack([sd.reshape(shape), sv.reshape(shape), sa.reshape(shape)])

    out = _batched(p.size, work, threads, run, axis=3)
    return out[0], out[1], out[2]


def rotd_peaks(
    pair: tuple[NDArray, NDArray], dt: float, p: NDArray, z: NDArray, n_angles: int,
    threads: int | None,
) -> NDArray:  # fmt: skip
    """Peaks of shape (dampings, periods, angles)."""
    work = float(pair[0].size * z.size * (2 + n_angles))

    def run(s: slice) -> NDArray:
        out = _core.rotd_peaks(pair, dt, p[s], z, n_angles, threads)
        return out.reshape(z.size, len(p[s]), n_angles)

    return _batched(p.size, work, threads, run, axis=1)


def ductility(
    a: NDArray, dt: float, p: NDArray, oscillator: tuple[float, float], mu: NDArray,
    threads: int | None,
) -> NDArray:  # fmt: skip
    """Yield displacements of shape (ductilities, periods); a bisection costs about 100
    runs of the oscillator per period and ductility."""
    work = float(100 * a.size * mu.size)

    def run(s: slice) -> NDArray:
        out = _core.ductility_spectrum(a, dt, p[s], oscillator, mu, threads)
        return out.reshape(mu.size, len(p[s]))

    return _batched(p.size, work, threads, run, axis=1)
