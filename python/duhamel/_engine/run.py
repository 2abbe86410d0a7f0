"""Running a route in the core: the Python load functions, the progress report, and the one
place where a run's failure becomes a Python exception (with the note of what the run tried,
:func:`failure_note`)."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.errors import SolverError

__all__ = [
    "ModalCallable",
    "Progress",
    "callback_error",
    "overflow_error",
    "raise_failure",
    "watch",
]

#: A progress report: ``(steps done, steps in all, time reached)``.
Progress = Callable[[int, int, float], Any]


class ModalCallable:
    """Sums the Python load functions (physical load vectors); called by the core with the
    GIL, once per evaluation time."""

    def __init__(self, fns: list[Any], n_dof: int) -> None:
        self.fns = fns
        self.n_dof = n_dof

    def __call__(self, t: float) -> NDArray[np.float64]:
        total = np.zeros(self.n_dof)
        for fn in self.fns:
            f = np.asarray(fn(t))
            if f.dtype.kind not in "iuf":
                raise TypeError(f"the `Callable` load returned dtype {f.dtype} at t = {t}")
            if f.shape != (self.n_dof,):
                raise ValueError(
                    f"the `Callable` load returned shape {f.shape} at t = {t}, "
                    f"expected ({self.n_dof},)"
                )
            if not np.all(np.isfinite(f)):
                raise ValueError(f"the `Callable` load returned NaN or inf at t = {t}")
            total += f
        return total


@contextlib.contextmanager
def watch(progress: bool | Progress | None, n_steps: int) -> Iterator[Progress | None]:
    """The progress function the core calls between blocks: None, the user's own, or a tqdm
    bar (``progress=True``) that shows itself only for runs lasting more than a second."""
    if progress is None or progress is False:
        yield None
        return
    if progress is True:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_steps, unit="step", delay=1.0, leave=False, desc="duhamel")

        def report(step: int, total: int, t: float) -> None:
            bar.update(step - bar.n)
            bar.set_postfix_str(f"t = {t:.6g}", refresh=False)

        try:
            yield report
        finally:
            bar.close()
        return
    if not callable(progress):
        raise TypeError(
            f"`progress` must be a bool or a function (step, n_steps, t), got "
            f"{type(progress).__name__}"
        )
    yield progress


def raise_failure(error: Any, partial: Any, note: str = "", step: int | None = None) -> None:
    """Raises the exception of a run that stopped early (`error`, a ``_core.RunError``),
    with the history kept, `partial`, attached as its ``partial`` attribute.

    * an interruption (Ctrl-C, also while a Python function runs) re-raises the
      ``KeyboardInterrupt`` (or a progress function's own exception);
    * a failing Python load or element function raises :class:`duhamel.SolverError` with
      ``reason="callback"``, chained (``from``) to the function's own exception;
    * otherwise :class:`duhamel.SolverError` with the core's fields, `note` appended to
      its message and `step` (the user's step, when the run took internal steps) in place
      of the core's.
    """
    cause = error.cause
    interrupted = error.kind == "interrupted" or (
        isinstance(cause, BaseException) and not isinstance(cause, Exception)
    )
    if interrupted:
        exc = cause if isinstance(cause, BaseException) else KeyboardInterrupt(error.message)
        exc.partial = partial  # type: ignore[attr-defined]
        exc.add_note(f"duhamel: {error.message}")
        raise exc
    if error.kind == "callback":
        what = f"{type(cause).__name__}: {cause}" if cause is not None else error.message
        raise callback_error(what, error.time, error.step, partial) from cause
    raise SolverError(
        error.message + note,
        time=error.time,
        reason=error.kind,
        partial=partial,
        step=error.step if step is None else step,
    )


def callback_error(what: str, time: float, step: int, partial: Any) -> SolverError:
    """The :class:`duhamel.SolverError` of a Python load or element function that failed
    (`what`: its exception, rendered) when called at `time` for `step`; the caller raises it
    ``from`` the function's exception."""
    kept = (
        f"the history up to t = {float(partial.t[-1])!r} is kept"
        if partial.t.size
        else "nothing is kept"
    )
    return SolverError(
        f"a Python load or element function failed at t = {time!r} (step {step}): {what}; {kept}",
        time=time,
        reason="callback",
        partial=partial,
        step=step,
    )


def overflow_error(t: Any, kept: int, dt: float, t0: float, partial: Any) -> SolverError:
    """The :class:`duhamel.SolverError` of a run whose physical outputs (``x``, ``v`` or
    ``a`` of the output dofs) overflow at saved row `kept` of the times `t` although the
    engine's state stayed finite; `partial` keeps the rows before it."""
    when = float(t[kept])
    step = round((when - t0) / dt)
    held = (
        f"the history up to t = {float(partial.t[-1])!r} is kept"
        if partial.t.size
        else "nothing is kept"
    )
    return SolverError(
        f"the physical response overflows the double range at t = {when!r} (step {step}): "
        "the model's scales (mass, stiffness, initial state, loads) put displacements, "
        f"velocities or accelerations beyond 1e308; {held}",
        time=when,
        reason="nonfinite",
        partial=partial,
        step=step,
    )


def failure_note(
    error: Any,
    modal: Any,
    *,
    forces: bool,
    route: str,
    omega: NDArray[np.float64],
    correction: NDArray[np.float64],
    subdivisions: int,
    dt: float,
    sub: int,
) -> str:
    """What a failed run with elements (`forces`) tried and which modal coordinate (of
    circular frequencies `omega`; `correction` those of the static-correction ones) diverged,
    from the `modal` history kept (None: not said); `dt` the internal step, `sub` internal
    steps per step. Appended to the message of a ``"convergence"`` or ``"nonfinite"``
    failure (empty otherwise)."""
    if error.kind not in ("convergence", "nonfinite") or not forces:
        return ""
    parts = []
    if sub > 1:
        parts.append(
            f"the run took {sub} internal steps per step (static-correction coordinates "
            f"resolved in time); the core's step {error.step} is internal"
        )
    if error.kind == "convergence" and route == "pseudo-force" and subdivisions > 0:
        parts.append(
            f"the step was retried in halves down to dt/{2**subdivisions} "
            f"(`subdivisions`={subdivisions}) and failed there too"
        )
    q = None if modal is None else getattr(modal, "q", None)
    if q is not None and q.ndim == 2 and q.shape[0] >= 8 and np.all(np.isfinite(q)):
        # The coordinate that grew most over the last quarter of the history against its
        # earlier peak: a divergence shows there before Newton gives up.
        cut = q.shape[0] * 3 // 4
        early = np.abs(q[:cut]).max(axis=0)
        late = np.abs(q[cut:]).max(axis=0)
        scale = max(float(early.max()), np.finfo(float).tiny)
        growth = late / np.maximum(early, 1e-12 * scale)
        i = int(np.argmax(growth))
        if growth[i] > 4.0:
            w = float(omega[i])
            kind = (
                "a static-correction coordinate"
                if np.any(np.isclose(correction, w, rtol=1e-12, atol=0.0))
                else "a mode"
            )
            parts.append(
                f"modal coordinate {i} ({kind}, omega dt = {w * dt:.3g}) grew "
                f"{growth[i]:.3g} times over its earlier peak before the failure: a diverging "
                "pseudo-force step, which a smaller `dt` (omega dt <= 1 on that coordinate) "
                "or, for a reduced model, more `modes` avoids; more `max_iter` does not"
            )
    return "" if not parts else " [" + "; ".join(parts) + "]"
