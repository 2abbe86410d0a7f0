"""Modes of a model with its force elements at a stated stiffness (:meth:`duhamel.System.modal`
with ``elements=``): ``K`` plus each element's initial stiffness (its tangent at ``x = 0``
in its initial state: a bearing's pre-sliding stiffness, a hinge's elastic stiffness, as
OpenSees' ``eigen`` sees them before the record), or plus each element's effective
stiffness at a displacement (ASCE 7-22 chapter 17's ``k_eff``, from the element's own loop,
:func:`duhamel.design.effective_properties`). ``M`` and the damping specification are the
system's: the modal damping is derived from them as for ``K`` alone."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["STIFFNESS_DEFAULT", "element_stiffness", "modal_with_elements"]

#: What :meth:`duhamel.System.modal` says of a model with force elements by default.
STIFFNESS_DEFAULT = (
    "K alone: the force elements' stiffness is not in these modes (modal(elements='initial') "
    "or elements='effective' with a displacement adds it)"
)


def _local_tangent(element: Any) -> NDArray[np.float64]:
    """The element's local tangent ``dr/dx`` at ``x = 0`` in its initial state."""
    from duhamel.elements import drive

    n = len(element._dofs)
    h = drive(element, np.zeros((1, n)))
    return np.asarray(h.tangent, dtype=np.float64).reshape(n, n)


def _effective(element: Any, displacement: float) -> NDArray[np.float64]:
    """The element's local stiffness at the amplitude `displacement`, from its definition's
    directions (:meth:`duhamel.elements.Element._directions`): a deformation ``x_i - x_j``
    at the ``k_eff`` of its loop (measured on the element to the ground); a device acting on
    each of its dofs alone at ``k_eff`` along each (its loop along the first); a bearing with
    its vertical dof at its horizontal loop's ``k_eff`` and its vertical tangent."""
    from duhamel.design.effective import effective_properties

    n = len(element._dofs)
    directions = element._directions()
    parameters = getattr(element, "parameters", None) or {}
    if len(directions) == 1 and directions[0][1] is not None and n == 2:
        keff = effective_properties(element.replace(j=None), displacement).stiffness
        return keff * np.array([[1.0, -1.0], [-1.0, 1.0]])
    if all(j is None for _, j in directions) and len(directions) == n:
        if "vertical_stiffness" in parameters and len(parameters.get("dofs") or ()) == 3:
            keff = effective_properties(element, displacement).stiffness  # its horizontal loop
            k = np.zeros((n, n))
            k[: n - 1, : n - 1] = keff * np.eye(n - 1)
            k[n - 1, n - 1] = parameters["vertical_stiffness"]
            return k
        if n <= 2:
            return effective_properties(element, displacement).stiffness * np.eye(n)
    raise ValueError(
        f"`elements`='effective': no effective stiffness for {type(element).__name__} (on "
        f"dofs {element._dofs}, acting along {directions}); use elements='initial'"
    )


def element_stiffness(
    system: Any, elements: str, displacement: float | None = None, nonsymmetric: bool = False
) -> NDArray[np.float64]:
    """``K`` plus the system's force elements' stiffness (``elements`` ``"initial"`` or
    ``"effective"`` at `displacement`), dense; symmetric, or with `nonsymmetric` the
    elements' tangents that are not symmetric added as they are."""
    if elements not in ("initial", "effective"):
        raise ValueError(f"`elements` must be 'initial' or 'effective', got {elements!r}")
    if elements == "effective":
        if displacement is None or not np.isfinite(displacement) or displacement <= 0:
            raise ValueError(
                f"`displacement` must be a positive amplitude with elements='effective', got "
                f"{displacement!r}"
            )
    elif displacement is not None:
        raise ValueError("`displacement` is for elements='effective' only")
    from duhamel._engine.validate import issparse
    from duhamel.elements import Callable

    K = system.K.toarray() if issparse(system.K) else np.array(system.K, dtype=np.float64)
    for element in system.elements:
        if isinstance(element, Callable) and (
            elements == "effective" or element.parameters.get("jacobian") is None
        ):
            raise ValueError(
                f"`elements`: a Callable defines no {elements} stiffness to add"
                + (
                    " (give it a `jacobian`: its tangent at x = 0 is then its initial stiffness)"
                    if elements == "initial"
                    else ""
                )
                + ": compute these modes from a stiffness of your own"
            )
        dofs = list(element._dofs)
        k = (
            _local_tangent(element)
            if elements == "initial"
            else _effective(element, float(displacement))  # type: ignore[arg-type]
        )
        if not np.all(np.isfinite(k)):
            raise ValueError(f"`elements`: {type(element).__name__}'s stiffness is not finite")
        if np.abs(k - k.T).max(initial=0.0) > 1e-9 * np.abs(k).max(initial=0.0):
            if not nonsymmetric:
                raise ValueError(
                    f"`elements`: {type(element).__name__}'s stiffness there is not symmetric "
                    "(no undamped modes with it)"
                )
            K[np.ix_(dofs, dofs)] += k  # as it is (a P-Delta tangent: the caller's modes)
        else:
            K[np.ix_(dofs, dofs)] += 0.5 * (k + k.T)
    return K


def _nonsymmetric_modes(system: Any, K: NDArray[np.float64], n_modes: int | None) -> Any:
    """The modes of ``(K, M)`` for a `K` that is not symmetric (an element's initial tangent
    that is not, such as the P-Delta moments of an imported elastomeric bearing): the real
    eigenvalues of the general problem (massless dofs give infinite ones, left out), the right
    eigenvectors mass-normalised, as OpenSees' ``eigen`` computes them on its tangent. Refused
    when an eigenvalue of the modes kept is complex or not positive."""
    import scipy.linalg

    from duhamel._engine.validate import issparse
    from duhamel.modal import damped

    M = system.M.toarray() if issparse(system.M) else np.asarray(system.M, dtype=np.float64)
    (alpha, beta), right = scipy.linalg.eig(K, M, right=True, homogeneous_eigvals=True)
    finite = np.abs(beta) > 1e-12 * np.abs(alpha)
    lam = alpha[finite] / beta[finite]
    phi = right[:, finite]
    order = np.argsort(lam.real)
    n = lam.size if n_modes is None else int(n_modes)
    if not 1 <= n <= lam.size:
        raise ValueError(f"`n_modes` must be in [1, {lam.size}], got {n_modes!r}")
    lam, phi = lam[order[:n]], phi[:, order[:n]]
    if np.any(np.abs(lam.imag) > 1e-8 * np.abs(lam.real)) or np.any(lam.real <= 0.0):
        raise ValueError(
            "`elements`: the stiffness with the elements' initial tangent is not symmetric "
            "and its lowest modes are not real and positive (no undamped modes with it)"
        )
    lam, phi = lam.real, phi.real
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))
    return damped(lam, phi, system)


def modal_with_elements(
    system: Any, n_modes: int | None, elements: str, displacement: float | None
) -> Any:
    """The modes of ``(K + the elements' stiffness, M)``, the statement of that stiffness
    in the basis (:meth:`duhamel.ModalBasis.summary`)."""
    K = element_stiffness(system, elements, displacement, nonsymmetric=elements == "initial")
    if np.abs(K - K.T).max(initial=0.0) > 1e-12 * np.abs(K).max(initial=0.0):
        basis = _nonsymmetric_modes(system, K, n_modes)
        what = (
            "K + the force elements' initial stiffness (their tangent at x = 0), not "
            "symmetric: the right eigenvectors of the general problem, mass-normalised but "
            "not mass-orthogonal (OpenSees' eigen on its tangent)"
        )
        return replace(basis, stiffness=what)
    basis = system._with_stiffness(K).modal(n_modes)
    what = (
        "K + the force elements' initial stiffness (their tangent at x = 0)"
        if elements == "initial"
        else f"K + the force elements' effective stiffness k_eff at D = {displacement:g}"
    )
    return replace(basis, stiffness=what)
