"""A system's damped modal basis: its modal analysis with the checks that turn a numerical
library's failure into a message about the inputs, or, for the first analysis of a fresh
system, the same analysis of an earlier system with the same matrices
(:mod:`duhamel._engine.shared`)."""

from __future__ import annotations

from dataclasses import fields
from typing import Any, cast

import numpy as np

from duhamel._engine import shared
from duhamel.modal import ModalBasis, damped

__all__ = ["check_supplied", "modal_basis", "owned"]


def modal_basis(system: Any, n: int) -> ModalBasis:
    """The damped basis of the lowest `n` modes of `system` (uncached: the system caches)."""
    modes = system._modes
    key = system._content if modes.count == 0 and not modes.supplied else None
    known = shared.basis(key, n, system)
    if known is not None:
        lam, phi, basis, semidefinite = known
        # This system's modes become those of the first analysis, as if computed here.
        modes.lam, modes.phi, modes._semidefinite = lam, phi, semidefinite
        return cast(ModalBasis, basis)
    basis = _checked_modal(system, n)
    if key is not None and modes.count == n:
        shared.remember_basis(key, n, system, (modes.lam, modes.phi, basis, modes._semidefinite))
    return basis


def _checked_modal(system: Any, n: int) -> ModalBasis:
    """The damped modal basis of `system`, or a ValueError naming the inputs when their
    scales are beyond what the eigensolvers can analyse in double precision (a numerical
    library's error, or non-finite modes or damping)."""
    import numpy.linalg
    import scipy.sparse.linalg as spla

    try:
        lam, phi = system._modes.lowest(n)
    except (
        numpy.linalg.LinAlgError,
        spla.ArpackError,
        spla.ArpackNoConvergence,
        ValueError,
    ) as exc:
        if isinstance(exc, ValueError) and str(exc).startswith("`"):
            raise  # our own, naming its parameter
        raise ValueError(
            f"the modal analysis of `M` and `K` failed ({type(exc).__name__}: {exc}): their "
            "scales are beyond what double precision can analyse (check their units and "
            "values)"
        ) from None
    with np.errstate(all="ignore"):
        finite = bool(np.all(np.isfinite(lam)) and np.all(np.isfinite(phi)))
    if not finite:
        raise ValueError(
            "the modal analysis of `M` and `K` gives non-finite modes: their scales are beyond "
            "what double precision can analyse (check their units and values)"
        )
    with np.errstate(all="ignore"):
        try:
            basis = damped(lam, phi, system)
        except (numpy.linalg.LinAlgError, ValueError) as exc:
            if isinstance(exc, ValueError) and str(exc).startswith("`"):
                raise
            raise ValueError(
                f"the modal damping of `C` cannot be computed ({type(exc).__name__}: {exc}): "
                "its scale is beyond what double precision can analyse"
            ) from None
        damping_ok = bool(np.all(np.isfinite(basis.c)) and np.all(np.isfinite(basis.zeta)))
        coupling_ok = basis.c_coupling is None or bool(np.all(np.isfinite(basis.c_coupling)))
    if not (damping_ok and coupling_ok):
        name = {"zeta": "zeta", "rayleigh": "rayleigh", "matrix": "C"}.get(
            system._damping, "damping"
        )
        raise ValueError(
            f"the modal damping from `{name}` overflows the double range for these modes: "
            f"check `{name}` (a damping ratio is a fraction of critical damping) and the "
            "model's units"
        )
    return basis


def check_supplied(system: Any, basis: ModalBasis, rtol: float) -> None:
    """Refuses a basis given to :meth:`duhamel.System.use_basis` that does not hold modes of
    `system` (size, mass-orthonormality, residuals to `rtol`)."""
    from duhamel.modal import backward_errors, orthonormality_error

    if basis.n_dof != system.n_dof:
        raise ValueError(
            f"`basis` holds modes of {basis.n_dof} degrees of freedom, the system has "
            f"{system.n_dof}"
        )
    error, (i, j) = orthonormality_error(basis.phi, system.M)
    if error > rtol:
        raise ValueError(
            f"`basis` is not mass-orthonormal with this system's `M`: entry ({i}, {j}) of "
            f"phi.T M phi - I is {error:.3g} > `rtol` = {rtol:g} (modes of another model?)"
        )
    residual = backward_errors(basis.phi, basis.omega2, system.M, system.K)
    worst = int(np.argmax(residual))
    if residual[worst] > rtol:
        raise ValueError(
            f"`basis` does not hold modes of this system's `K` and `M`: mode {worst} "
            f"(omega = {basis.omega[worst]:.6g} rad/s) has the relative residual "
            f"|K phi - omega2 M phi| / ((|K| + omega2 |M|) |phi|) = {residual[worst]:.3g} "
            f"> `rtol` = {rtol:g}"
        )


#: The fields of :class:`~duhamel.ModalBasis` (:func:`owned`).
_BASIS_FIELDS = tuple(f.name for f in fields(ModalBasis))


def owned(basis: ModalBasis, labels: Any, mass: Any, stiffness: str) -> ModalBasis:
    """`basis` (the same arrays) with a system's `labels`, `mass` and `stiffness` statement:
    ``dataclasses.replace`` without its per-field walk (a system whose first modal analysis
    is shared with other systems of the same matrices does this on its first run)."""
    other = object.__new__(ModalBasis)
    held = basis.__dict__
    other.__dict__.update({name: held[name] for name in _BASIS_FIELDS})
    other.__dict__.update(labels=labels, mass=mass, stiffness=stiffness)
    return other
