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
    """The element's local stiffness at the amplitude `displacement`: ``k_eff`` along each
    of its directions (a bearing's horizontal ones; its vertical dof at its tangent)."""
    from duhamel.design.effective import effective_properties, horizontal_bearing
    from duhamel.elements import FrictionPendulum

    n = len(element._dofs)
    k = np.zeros((n, n))
    name = type(element).__name__
    if isinstance(element, FrictionPendulum) and len(element.dofs) == 3:
        # the horizontal loop under the axial force at x = 0 (its weight: nominal)
        horizontal = horizontal_bearing(element)
        keff = effective_properties(horizontal, displacement).stiffness
        m = n - 1
        k[:m, :m] = keff * np.eye(m)
        k[m, m] = element.vertical_stiffness
        return k
    if name in ("FrictionPendulum", "TripleFrictionPendulum", "LeadRubberBearing") or n == 1:
        return effective_properties(element, displacement).stiffness * np.eye(n)
    if n == 2 and name in ("Bilinear", "BoucWen"):
        keff = effective_properties(element.replace(j=None), displacement).stiffness
        return keff * np.array([[1.0, -1.0], [-1.0, 1.0]])
    raise ValueError(
        f"`elements`='effective': no effective stiffness for {name} (on dofs "
        f"{element.dofs}); use elements='initial'"
    )


def element_stiffness(
    system: Any, elements: str, displacement: float | None = None
) -> NDArray[np.float64]:
    """``K`` plus the system's force elements' stiffness (``elements`` ``"initial"`` or
    ``"effective"`` at `displacement`), dense, symmetric."""
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
        if isinstance(element, Callable):
            raise ValueError(
                f"`elements`: {type(element).__name__} defines no stiffness to add (a "
                "Callable): compute these modes from a stiffness of your own"
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
            raise ValueError(
                f"`elements`: {type(element).__name__}'s stiffness there is not symmetric "
                "(no undamped modes with it)"
            )
        K[np.ix_(dofs, dofs)] += 0.5 * (k + k.T)
    return K


def modal_with_elements(
    system: Any, n_modes: int | None, elements: str, displacement: float | None
) -> Any:
    """The modes of ``(K + the elements' stiffness, M)``, the statement of that stiffness
    in the basis (:meth:`duhamel.ModalBasis.summary`)."""
    K = element_stiffness(system, elements, displacement)
    basis = system._with_stiffness(K).modal(n_modes)
    what = (
        "K + the force elements' initial stiffness (their tangent at x = 0)"
        if elements == "initial"
        else f"K + the force elements' effective stiffness k_eff at D = {displacement:g}"
    )
    return replace(basis, stiffness=what)
