"""Models from OpenSees: :func:`from_opensees` reads the model defined in the running
openseespy session (``pip install 'duhamel[opensees]'``) and returns a labelled
:class:`duhamel.System` (docs/models.md)."""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.labels import Labels
from duhamel.elements import Element
from duhamel.opensees._recording import Recording, recording
from duhamel.system import System

__all__ = ["OpenSeesModel", "Recording", "from_opensees", "recording"]


@dataclass
class OpenSeesModel:
    """What :func:`from_opensees` read besides the matrices (``system.opensees``).

    Attributes
    ----------
    labels : list of (int, str)
        The ``(node, component)`` label of each dof of the system, in dof order.
    x0 : ndarray
        The displacements of the dofs at import (after a gravity analysis: the displaced
        state). duhamel's response is measured from this state: add `x0` for totals.
    elements : dict
        The duhamel elements made from each translated OpenSees element, by element tag.
    linearized : dict
        The elements kept linear (``nonlinear="linearize"``), ``{tag: type}``.
    recovery : dict
        Every non-fixed node dof as a row of coefficients on the system's dofs (the nodes
        tied by a rigid diaphragm or link are no dofs of the system; :meth:`node_response`
        gives their motion).
    notes : list of str
        What the translation assumed (e.g. the friction coefficient taken at import).
    """

    labels: list[tuple[int, str]]
    x0: NDArray[np.float64]
    elements: dict[int, list[Element]] = field(default_factory=dict)
    linearized: dict[int, str] = field(default_factory=dict)
    recovery: dict[tuple[int, str], NDArray[np.float64]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def node_response(self, x: ArrayLike, node: int, component: str) -> NDArray[np.float64]:
        """The motion of a node dof from a response `x` on every dof (``sol.x``, shape
        ``(n_times, n_dof)``), also for the dofs OpenSees ties by constraints.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.opensees import OpenSeesModel
        >>> m = OpenSeesModel([(1, "ux")], np.zeros(1), recovery={(2, "ux"): np.array([1.0])})
        >>> m.node_response(np.ones((3, 1)), 2, "ux").tolist()
        [1.0, 1.0, 1.0]
        """
        row = self.recovery.get((int(node), str(component)))
        if row is None:
            raise ValueError(f"`node` {node} {component!r} is fixed or not in the model")
        return np.asarray(x, dtype=np.float64) @ row


def _openseespy() -> Any:
    try:
        import openseespy.opensees as ops
    except ImportError as exc:  # also a wheel whose BLAS/LAPACK is missing
        raise ImportError(
            "duhamel.opensees needs openseespy: pip install 'duhamel[opensees]' (its wheel "
            f"needs the system BLAS and LAPACK, e.g. apt install libblas3 liblapack3): {exc}"
        ) from exc
    return ops


def _rayleigh_check(damped: dict[int, Any], rayleigh: Any) -> list[str]:
    """Refuses Rayleigh damping on translated (nonlinear) elements unless it is proportional
    to their initial stiffness (`rayleigh`'s ``betaK0``: a linear dashpot, kept in ``C``);
    returns the notes of those kept."""
    if not damped:
        return []
    tag, d = next(iter(damped.items()))
    name = f"OpenSees element {tag} ({d.kind}, {d.what})"
    if rayleigh is None:
        raise ValueError(
            f"{name} carries Rayleigh damping (defined with '-doRayleigh'): OpenSees makes "
            "its stiffness-proportional part follow the element's initial stiffness "
            "(rayleigh's betaK0), current tangent (betaK) or last committed tangent "
            "(betaKc), which the import cannot read back from OpenSees; pass the factors "
            "given to ops.rayleigh as `rayleigh=(alphaM, betaK, betaK0, betaKc)`, or define "
            "the element without '-doRayleigh' (zeroLength's default)"
        )
    from duhamel._engine.validate import as_float_array

    _, beta_k, beta_k0, beta_kc = as_float_array(rayleigh, "rayleigh", shape=(4,)).tolist()
    for value, key, tangent in (
        (beta_k, "betaK", "current tangent (it changes as the element yields)"),
        (beta_kc, "betaKc", "last committed tangent (its tangent at the start of each "
         "of OpenSees' steps, a damping that also depends on the step)"),
    ):  # fmt: skip
        if value != 0.0:
            raise ValueError(
                f"`rayleigh`: {key} = {value:g} damps {name} in proportion to its {tangent}: "
                "a state-dependent damping that duhamel's elements do not model; damp it on "
                "its initial stiffness (betaK0, a linear dashpot duhamel keeps exactly) or "
                "define it without '-doRayleigh'"
            )
    notes = []
    for tag, d in damped.items():
        for k0, c in d.directions:
            want = beta_k0 * k0
            if np.isfinite(c) and abs(c - want) > 1e-8 * max(abs(c), abs(want)):
                raise ValueError(
                    f"`rayleigh`: OpenSees element {tag} ({d.kind}) is damped with "
                    f"{c:.6g} at import, betaK0 times its stiffness is {want:.6g}: these are "
                    "not the factors OpenSees used for it (a region with others?)"
                )
        notes.append(
            f"element {tag}: OpenSees' Rayleigh damping on its initial stiffness (betaK0 = "
            f"{beta_k0:g}) kept in C as a linear dashpot"
        )
    return notes


def _skew(K: NDArray[np.float64], labels: list, notes: list[str]) -> NDArray | None:
    """The skew-symmetric part of OpenSees' tangent `K` when it is not symmetric to
    round-off (an elastomeric bearing's P-Delta moments: ``0.5 N`` times the shear
    displacement on its rotations, without the symmetric counterpart), else None. The
    system keeps it exactly, as a :class:`~duhamel.couplings.LinearCoupling`."""
    skew = 0.5 * (K - K.T)
    if not np.abs(skew).max(initial=0.0) > 1e-10 * np.abs(K).max(initial=0.0):
        return None
    a, b = np.unravel_index(int(np.argmax(np.abs(skew))), skew.shape)
    notes.append(
        f"OpenSees' tangent stiffness is not symmetric (largest between {labels[a]} and "
        f"{labels[b]}: a bearing's P-Delta moments): its skew part is kept as a "
        "linear Callable element (system.elements), K holds the symmetric part"
    )
    return skew


def _skew_element(skew: NDArray[np.float64]) -> Element:
    """The force ``skew @ x`` on the dofs it couples, as a linear element (the modal route
    keeps elements at massless dofs exactly, where the bearings' rotations are)."""
    from duhamel.elements import Callable

    dofs = np.flatnonzero(np.any(skew != 0.0, axis=0) | np.any(skew != 0.0, axis=1))
    local = np.ascontiguousarray(skew[np.ix_(dofs, dofs)])
    zero = np.zeros_like(local)

    def force(x: NDArray, v: NDArray, t: float) -> NDArray:
        return local @ x

    def jacobian(x: NDArray, v: NDArray, t: float) -> tuple[NDArray, NDArray]:
        return local, zero

    return Callable([int(d) for d in dofs], force, jacobian)


def _remove(K: NDArray[np.float64], dofs: tuple[int, ...], k: NDArray[np.float64]) -> None:
    """Takes a translated element's stiffness `k` on `dofs` out of `K` in place; what cancels
    to round-off is the element's own stiffness, computed here and by OpenSees in different
    ways (a triple pendulum's series stiffness): exactly zero. Entry by entry for distinct
    dofs (the same operations as on the block, without its fancy indexing)."""
    if len(set(dofs)) != len(dofs):
        left = K[np.ix_(dofs, dofs)] - k
        left[np.abs(left) <= 1e-12 * np.abs(k)] = 0.0
        K[np.ix_(dofs, dofs)] = left
        return
    for a, da in enumerate(dofs):
        for b, db in enumerate(dofs):
            left = K[da, db] - k[a, b]
            K[da, db] = 0.0 if abs(left) <= 1e-12 * abs(k[a, b]) else left


def _analysed(ops: Any) -> bool:
    """Whether the model has been analysed: a node displaced, moving or accelerating."""
    for node in ops.getNodeTags():
        for f in (ops.nodeDisp, ops.nodeVel, ops.nodeAccel):
            values = f(node)
            if any(v != 0.0 for v in (values if isinstance(values, list) else [values])):
                return True
    return False


def from_opensees(
    *,
    nonlinear: Literal["translate", "linearize"] = "translate",
    rayleigh: tuple[float, float, float, float] | None = None,
    recorded: Recording | None = None,
) -> System:
    """The model defined in the running openseespy session as a labelled :class:`System`.

    ``M``, ``K`` and, when ``rayleigh`` or element damping is defined, ``C`` are formed by
    OpenSees (``integrator('GimmeMCK', ...)``, ``system('FullGeneral')``, ``printA``) at
    the current state: after a gravity analysis, ``K`` is the tangent with its geometric
    stiffness. Fixities and multi-point constraints (``equalDOF``, ``rigidDiaphragm``,
    ``rigidLink``) are applied by transformation: every equation is one dof of the system,
    labelled ``(node, component)`` with components ``"ux"``, ``"uy"``, ``"uz"``, ``"rx"``,
    ``"ry"``, ``"rz"``; dofs tied one to one (``equalDOF``) are aliases of it. The session's
    analysis objects are replaced (define them again before running OpenSees).

    Nonlinear elements are translated to duhamel's (docs/models.md lists each):
    ``zeroLength`` and ``twoNodeLink`` (coincident nodes) with ``Steel01``
    (:class:`~duhamel.elements.Bilinear`), ``BoucWen``, ``ViscousDamper`` (a dashpot),
    ``ElasticPPGap`` without yield and ``ENT`` (:class:`~duhamel.elements.Gap`) materials,
    ``Steel02``, ``ModIMKPeakOriented``, ``IMKBilin``, ``Hysteretic``,
    ``ElasticMultiLinear``, ``Pinching4`` and ``MultiLinear`` (these two with `recorded`:
    OpenSees does not print their parameters) and ``MinMax``/``Parallel``/``Series`` of
    them (the element of the same name) (``Elastic`` stays in ``K``); ``flatSliderBearing`` and
    ``singleFPBearing`` (2-D and 3-D) as :class:`~duhamel.elements.FrictionPendulum` with
    their vertical dof and the axial force at import (friction and restoring force follow
    the axial force);
    ``TripleFrictionPendulum`` (3-D, under its axial load at import);
    ``elastomericBearingPlasticity`` and ``elastomericBearingBoucWen`` as their bilinear and
    Bouc-Wen shear with OpenSees' P-Delta moments. Their stiffness at import is taken out of
    ``K``. The import runs after a gravity analysis (``loadConst``): ``K`` is the tangent
    there, and each translated element starts in its state at import (a ``Steel01`` hinge
    with the rotation and moment the gravity loads left, elastic or yielded, as the
    Bilinear's ``initial_deformation``/``initial_force``; every other translated uniaxial
    material with its strain as the element's ``initial_deformation``, which duhamel's
    material reaches from rest monotonically, checked against OpenSees' stress and tangent
    there to 1e-6; an open gap with the distance left to contact); a state that cannot be
    carried over (a hinge unloaded during the gravity analysis, a loaded ``BoucWen``) is
    refused naming the element and material. The response is measured from the state at
    import: totals are ``system.opensees.x0 + sol.x`` (the model carries no gravity load,
    so do not pass ``x0`` to :func:`duhamel.solve`). Massless dofs that the damping matrix
    reaches (a hinge's rotation under ``betaK``) are first-order coordinates of the model,
    not static (:meth:`System.damping_summary` says which). Models OpenSees cannot analyse (no free
    dof, a constraint loop, coordinates that are not finite) are refused before OpenSees
    runs.

    Parameters
    ----------
    nonlinear : {"translate", "linearize"}
        What to do with an element without a duhamel counterpart: refuse the model naming
        its tag and type (``"translate"``), or keep it at its tangent stiffness at import
        with a warning (``"linearize"``).
    rayleigh : (float, float, float, float), optional
        The factors ``(alphaM, betaK, betaK0, betaKc)`` given to OpenSees' ``rayleigh``, needed
        only when a translated element carries Rayleigh damping (a ``zeroLength`` or bearing
        defined with ``-doRayleigh``): on its initial stiffness (``betaK0``) that damping is a
        linear dashpot, kept exactly in ``C``; on its current or last committed tangent
        (``betaK``, ``betaKc``) it changes with the element's state, which duhamel does not
        model: refused. OpenSees does not let the import read these factors back. The
        elastic elements' Rayleigh damping is the same for every variant (their tangent is
        constant) and needs nothing.
    recorded : Recording, optional
        The arguments of the model's ``uniaxialMaterial`` and ``element`` commands, kept by
        :func:`recording` while the model was built (or written by hand): the parameters of
        its ``Pinching4`` and ``MultiLinear`` materials, which OpenSees does not print, and
        the material tags a ``zeroLength`` or wrapper prints as 0 (a ``MultiLinear``'s).
        Checked against the printed model: a recorded tag that is not in the model, of
        another type, with other points or material tags than OpenSees prints, or with
        arguments OpenSees' parser would not take is refused naming it. Without it, those
        two materials are refused (saying how to record them).

    Returns
    -------
    System
        With ``system.opensees``, an :class:`OpenSeesModel` (labels, ``x0``, the elements
        made from each OpenSees element, the recovery of constrained nodes).

    Raises
    ------
    ImportError
        If openseespy cannot be loaded.
    TypeError
        If `recorded` is not a :class:`Recording`.
    ValueError
        If `recorded` disagrees with the model or holds arguments OpenSees' parser would
        not take (naming the material or element), the session holds no model, an
        element cannot be translated or its state at
        import cannot be carried over (naming the element and material), Rayleigh damping
        on a translated element cannot be kept exactly, a node's coordinates are not
        finite, every dof is fixed (or tied to another node), or the multi-point
        constraints tie a dof back to itself (``equalDOF`` 2 -> 3 and 3 -> 2): refused
        before OpenSees analyses the model, whose numbering of the last two ends the Python
        process.

    Examples
    --------
    A mass on a ``Steel01`` spring (yield force 2, stiffness 40, hardening 0.1) under a
    constant load of 1 applied first (the gravity analysis), then a base acceleration:

    >>> import numpy as np
    >>> import openseespy.opensees as ops
    >>> import duhamel, duhamel.opensees
    >>> ops.wipe(); ops.model("basic", "-ndm", 1, "-ndf", 1)
    >>> ops.node(1, 0.0); ops.node(2, 0.0); ops.fix(1, 1); ops.mass(2, 1.0)
    >>> ops.uniaxialMaterial("Steel01", 1, 2.0, 40.0, 0.1)
    >>> ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1)
    >>> ops.timeSeries("Linear", 1); ops.pattern("Plain", 1, 1); ops.load(2, 1.0)
    >>> ops.constraints("Plain"); ops.numberer("Plain"); ops.system("FullGeneral")
    >>> ops.algorithm("Newton"); ops.integrator("LoadControl", 1.0); ops.analysis("Static")
    >>> ops.analyze(1)
    0
    >>> ops.loadConst("-time", 0.0)
    >>> system = duhamel.opensees.from_opensees()
    >>> system.dof_labels, system.opensees.x0
    (('2:ux',), array([0.025]))
    >>> system.opensees.elements[1]  # doctest: +NORMALIZE_WHITESPACE
    [Bilinear(0, None, k=40.0, fy=2.0, alpha=0.1, initial_deformation=0.025,
              initial_force=1.0)]
    >>> t = np.linspace(0.0, 2.0, 201)
    >>> record = duhamel.loads.BaseAcceleration("ux", t=t, values=3.0 * np.sin(2 * np.pi * t))
    >>> _ = system.add_load(record)
    >>> sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=0.0025)
    >>> peak = np.abs(system.opensees.x0[0] + sol.x[:, 0]).max()  # the total displacement
    >>> round(float(peak), 4)  # OpenSees' Newmark at dt = 2.5 ms: 0.396877
    0.3969
    """
    from duhamel.opensees._constraints import check_model, constraints
    from duhamel.opensees._read import dof_map, matrices, printout
    from duhamel.opensees._translate import translate

    if nonlinear not in ("translate", "linearize"):
        raise ValueError(f"`nonlinear` must be 'translate' or 'linearize', got {nonlinear!r}")
    ops = _openseespy()
    if not list(ops.getNodeTags()):
        raise ValueError("the openseespy session holds no model (no nodes)")
    pr = printout(ops)
    pr.constraints = constraints(ops)
    if recorded is not None:
        from duhamel.opensees._recording import apply

        apply(recorded, pr, [int(v) for v in ops.getEleTags()])
    check_model(ops, pr.constraints)  # before OpenSees numbers it: what ends the process
    M, C, K, equations = matrices(ops)
    dmap = dof_map(ops, M.shape[0], equations, pr.constraints)
    tr = translate(ops, pr, dmap, nonlinear)
    tr.notes.extend(_rayleigh_check(tr.damped, rayleigh))
    K = K.copy()
    for dofs, k in tr.removed:
        _remove(K, dofs, k)
    from duhamel.opensees._bearings import pdelta_elements
    from duhamel.opensees._materials import newton_damping

    followers = pdelta_elements(K, tr.pdelta, tr.notes)
    C = C.copy()
    newton = newton_damping(tr.elements, lambda: _analysed(ops))
    for dofs, c in newton:
        C[np.ix_(dofs, dofs)] -= c
    if newton:
        tr.notes.append(
            "ModIMKPeakOriented: its stiffness tangent, which OpenSees adds to the damping "
            "matrix (getDampTangent) with no damping force, left out of C"
        )
    skew = _skew(K, dmap.labels, tr.notes)
    if skew is not None:
        K = K - skew
    system = System(M, K, C=C) if np.any(C) else System(M, K)
    absent: dict[Hashable, str] = dict(dmap.absent)
    # System.label_dofs' two attributes, with the aliases and absent dofs (one Labels)
    system._label_map = Labels(dmap.labels, dmap.aliases, absent, n_dof=system.n_dof)
    system._labels = system._label_map.texts
    for element in followers:
        system.add(element)
    if skew is not None:
        system.add(_skew_element(skew))
    for made in tr.elements.values():
        for element in made:
            system.add(element)
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    from duhamel.opensees._read import components

    disp: dict[int, tuple[list[float], tuple[str, ...]]] = {}
    for node in {node for node, _ in dmap.labels}:
        disp[node] = (ops.nodeDisp(node), components(ndm, len(equations[node])))
    x0 = np.array(
        [disp[node][0][disp[node][1].index(comp)] for node, comp in dmap.labels],
        dtype=np.float64,
    )
    system.opensees = OpenSeesModel(  # type: ignore[attr-defined]
        labels=list(dmap.labels),
        x0=x0,
        elements=tr.elements,
        linearized=tr.linearized,
        recovery=dmap.recovery,
        notes=tr.notes,
    )
    return system
