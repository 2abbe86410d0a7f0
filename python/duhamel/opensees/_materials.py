"""OpenSees' uniaxial materials of issue 37 as duhamel's elements of the same name: Steel02,
ModIMKPeakOriented, IMKBilin, Hysteretic, ElasticMultiLinear and the wrappers MinMax,
Parallel and Series of them, from the parameters OpenSees prints (``printModel -JSON``, six
significant digits); Pinching4 and MultiLinear, which OpenSees prints without their
parameters (a zeroLength prints a MultiLinear's tag as 0), from the arguments recorded while
the model was built (``_recording.py``). Refused, naming the material: those two without a
recording, and an asymmetric law whose deformation duhamel would have to mirror (the node
with the material's positive deformation fixed). :func:`newton_damping`: the damping
OpenSees' ``ModIMKPeakOriented`` adds to the damping matrix without any damping force (taken
out of the imported ``C``)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.elements import (
    ElasticMultiLinear,
    Element,
    Hysteretic,
    IMKBilin,
    MinMax,
    ModIMKPeakOriented,
    Parallel,
    Series,
    Steel02,
    drive,
)
from duhamel.opensees._parts import Untranslatable, _pair

__all__ = ["KINDS", "material_element", "newton_damping"]

#: ModIMKPeakOriented's printed names -> duhamel's
_IMK = {
    "Ke0": "K0", "AlfaPos": "as_plus", "AlfaNeg": "as_neg", "My_pos": "My_plus",
    "My_neg": "My_neg", "Ls": "lambda_s", "Ld": "lambda_c", "La": "lambda_a",
    "Lk": "lambda_k", "Cs": "c_s", "Cd": "c_c", "Ca": "c_a", "Ck": "c_k",
    "ThetaPpos": "theta_p_plus", "ThetaPneg": "theta_p_neg", "ThetaPCpos": "theta_pc_plus",
    "ThetaPCneg": "theta_pc_neg", "ResfacPos": "res_plus", "ResfacNeg": "res_neg",
    "FracDispPos": "theta_u_plus", "FracDispNeg": "theta_u_neg", "DPos": "D_plus",
    "DNeg": "D_neg", "nFactor": "n_factor",
}  # fmt: skip
#: IMKBilin's printed names (OpenSees prints it as type "IMKPeakOriented", without the
#: ``Lamda_A`` of that material) -> duhamel's
_BILIN = {
    "Ke": "Ke", "dp_pos": "theta_p_plus", "dpc_pos": "theta_pc_plus", "du_pos": "theta_u_plus",
    "Fy_pos": "My_plus", "FmaxFy_pos": "Mmax_My_plus", "FresFy_pos": "res_plus",
    "dp_neg": "theta_p_neg", "dpc_neg": "theta_pc_neg", "du_neg": "theta_u_neg",
    "Fy_neg": "My_neg", "FmaxFy_neg": "Mmax_My_neg", "FresFy_neg": "res_neg",
    "Lamda_S": "lambda_s", "Lamda_C": "lambda_c", "Lamda_K": "lambda_k", "c_S": "c_s",
    "c_C": "c_c", "c_K": "c_k", "D_pos": "D_plus", "D_neg": "D_neg",
}  # fmt: skip
_HYST = {
    **{f"{x}{k}{s}": f"{x}{k}{s}" for x in "se" for k in "123" for s in "pn"},
    "pinchX": "pinch_x", "pinchY": "pinch_y", "damfc1": "damage1", "damfc2": "damage2",
    "beta": "beta",
}  # fmt: skip

#: The printed types translated here.
KINDS = (
    "Steel02",
    "ModIMKPeakOriented",
    "IMKPeakOriented",
    "HystereticMaterial",
    "ElasticMultiLinear",
    "MinMaxMaterial",
    "ParallelMaterial",
    "SeriesMaterial",
    "Pinching4Material",
    "MultiLinear",
)
#: Laws equal to their mirror image (``F(-u) = -F(u)`` on every path).
_SYMMETRIC = ("ElasticMultiLinear",)


def _named(mat: dict[str, Any], names: dict[str, str]) -> dict[str, float]:
    missing = [k for k in names if k not in mat]
    if missing:
        raise Untranslatable(
            f"{mat.get('type')} material {mat.get('name')}: OpenSees printed no {missing[0]}"
        )
    return {names[k]: float(mat[k]) for k in names}


def _symmetric(mat: dict[str, Any], materials: dict[int, dict[str, Any]]) -> bool:
    kind = str(mat.get("type"))
    if kind == "MultiLinear":  # a symmetric backbone, kinematic hardening
        return True
    if kind in _SYMMETRIC:
        points = sorted(zip(mat["strainPoints"], mat["stressPoints"], strict=True))
        return points == sorted((-float(e), -float(f)) for e, f in points)
    if kind in ("ParallelMaterial", "SeriesMaterial"):
        return all(_symmetric(materials.get(int(m), {}), materials) for m in mat["materials"])
    return False


def material_element(
    mat: dict[str, Any], materials: dict[int, dict[str, Any]], a: int | None, b: int | None
) -> Element:
    """The duhamel element of the OpenSees material `mat` on the deformation ``x_a - x_b``
    (OpenSees' strain; `materials`: the printed materials by tag, for a wrapper's parts)."""
    kind = str(mat.get("type"))
    name = f"{kind} material {mat.get('name')}"
    if a is None:
        if not _symmetric(mat, materials):
            raise Untranslatable(
                f"{name} with its positive deformation towards a fixed node (the node given "
                "second is fixed): duhamel would have to mirror the law; give the fixed node "
                "first"
            )
        a, b = b, None
    i, j = a, b
    if kind == "Steel02":
        p = _named(mat, {"fy": "fy", "E": "E", "b": "b", "R0": "R0", "cR1": "cR1"})
        p |= _named(mat, {"cR2": "cR2", "a1": "a1", "a2": "a2", "a3": "a3", "a4": "a4"})
        return Steel02(i, j, **p, sig_init=float(mat.get("sigini", 0.0)))
    if kind == "ModIMKPeakOriented":
        return ModIMKPeakOriented(i, j, **_named(mat, _IMK))
    if kind == "IMKPeakOriented":
        if "Lamda_A" in mat:
            raise Untranslatable(f"{name} (IMKPeakOriented: no duhamel counterpart)")
        return IMKBilin(i, j, **_named(mat, _BILIN))
    if kind == "HystereticMaterial":
        return Hysteretic(i, j, **_named(mat, _HYST))
    if kind == "ElasticMultiLinear":
        if float(mat.get("eta", 0.0)) != 0.0:
            raise Untranslatable(f"{name} with damping (eta != 0)")
        strain = [float(v) for v in mat["strainPoints"]]
        stress = [float(v) for v in mat["stressPoints"]]
        return ElasticMultiLinear(i, j, strain=strain, stress=stress)
    if kind in ("MinMaxMaterial", "ParallelMaterial", "SeriesMaterial"):
        tags = [mat["material"]] if kind == "MinMaxMaterial" else list(mat["materials"])
        parts = []
        for tag in tags:
            part = materials.get(int(tag))
            if part is None and int(tag) == 0:
                raise Untranslatable(
                    f"{name}: a part is printed with tag 0 (OpenSees' copy lost its tag, as a "
                    "MultiLinear's does); "
                    + mat.get(
                        "_unseen",
                        "build the model inside `with duhamel.opensees.recording() as rec:` "
                        "and import it with `from_opensees(recorded=rec)`",
                    )
                )
            if part is None:
                raise Untranslatable(f"{name}: its part {tag} (not printed by OpenSees)")
            parts.append(material_element(part, materials, i, j))
        if kind == "MinMaxMaterial":
            lo, hi = float(mat["epsMin"]), float(mat["epsMax"])
            return MinMax(i, j, material=parts[0], min=lo, max=hi)
        if kind == "SeriesMaterial":
            return Series(i, j, materials=parts)
        factors = mat.get("factors")
        return Parallel(
            i, j, materials=parts, factors=None if factors is None else [float(f) for f in factors]
        )
    if kind in ("Pinching4Material", "MultiLinear"):
        if "_recorded" not in mat:  # the arguments given to OpenSees (_recording.apply)
            raise Untranslatable(
                f"{name}: OpenSees prints none of its parameters (only its state), so it "
                "cannot be read back; "
                + mat.get(
                    "_unseen",
                    "build the model inside `with duhamel.opensees.recording() as rec:` "
                    "and import it with `from_opensees(recorded=rec)`",
                )
            )
        cls, params = mat["_recorded"]
        return cls(i, j, **params)  # type: ignore[no-any-return]
    raise Untranslatable(f"{name}: no duhamel counterpart")


def _inner(element: Element) -> list[Element]:
    p = element.parameters  # type: ignore[attr-defined]
    return [p["material"]] if "material" in p else list(p.get("materials", ()))


def _tangent_at_import(element: Element) -> float:
    """A ``ModIMKPeakOriented``'s stiffness tangent at import: ``K0 (1 + n_factor)`` at
    zero deformation, else its tangent at its ``initial_deformation`` reached from rest
    (the import checked it equals OpenSees' there)."""
    p = element.parameters  # type: ignore[attr-defined]
    d0 = float(p.get("initial_deformation", 0.0))
    if d0 == 0.0:
        return float(p["K0"] * (1.0 + p["n_factor"]))
    virgin = element.replace(initial_deformation=0.0)  # type: ignore[attr-defined]
    return float(drive(virgin, np.linspace(0.0, d0, 101)).tangent[-1])


def newton_damping(
    elements: dict[int, list[Element]], analysed: Callable[[], bool]
) -> list[tuple[tuple[int, ...], NDArray[np.float64]]]:
    """The damping matrix terms, each ``(dofs, c)``, that OpenSees' ``ModIMKPeakOriented``
    puts into the damping matrix with no damping force behind them: its ``getDampTangent``
    returns ``ekP``, its stiffness tangent at its last update (0 before any), which
    ``ZeroLength::getDamp`` adds to the damping matrix, while its force (``getStress``) has
    no rate term. They enter only OpenSees' Newton matrix, not its model's response, so they
    are taken out of the damping matrix read from OpenSees. After an analysis (e.g. the
    gravity loads; `analysed()` says, asked only when such a material is translated) each
    such material has its tangent at its state at import (``K0 (1 + n_factor)`` at zero
    deformation); before any, ``ekP`` is 0. A
    wrapper (MinMax, Parallel, Series) of one after an analysis is refused: OpenSees'
    wrappers combine their parts' damping tangents in ways not read here."""
    out = []
    after: list[bool] = []  # analysed(), asked once and only for these materials
    for tag, made in elements.items():
        for element in made:
            if not isinstance(element, (ModIMKPeakOriented, MinMax, Parallel, Series)):
                continue
            if not after:
                after.append(analysed())
            if not after[0]:
                continue
            if isinstance(element, ModIMKPeakOriented):
                p = element.parameters  # type: ignore[attr-defined]
                out.append(_pair(p["i"], p["j"], _tangent_at_import(element)))
                continue
            stack = _inner(element)
            while stack:
                part = stack.pop()
                if isinstance(part, ModIMKPeakOriented):
                    raise ValueError(
                        f"cannot translate OpenSees element {tag}: a {type(element).__name__} "
                        "with a ModIMKPeakOriented part after an analysis (OpenSees adds that "
                        "material's stiffness tangent to the damping matrix, a term the "
                        "import cannot separate inside a wrapper); define the hinge's "
                        "materials without the wrapper or import before the analysis"
                    )
                stack.extend(_inner(part))
    return out
