"""Type stub of the native module ``duhamel._core`` (Rust, PyO3).

Every input is a typed class of this module, extracted into Rust values once: time
functions, speed and mass laws, elements, loads and matrices; a prepared :class:`ModalModel`
with its route (None: uncoupled oscillators; :class:`FirstOrderRoute` or
:class:`PseudoForceRoute`) or a :class:`DirectModel` on its :class:`Matrices`. A run takes
its grid and initial state as a :class:`RunSpec` (modal) or a :class:`DirectRun` (direct),
each on a :class:`Grid`, and returns a :class:`RunResult`. A class refuses a value of the
wrong type, dtype or layout when made (and a value it can check alone: an unknown option, a
non-finite load pattern); sizes, ranges and finiteness against the model are checked when
the run starts; either way with a ``TypeError`` or ``ValueError`` naming the value (for a
wrong type, in the exception's note). Nothing is read from the attributes of Python objects
(``duhamel._engine.dispatch`` builds these inputs). ``tests/project/test_stub.py`` checks that this
stub names every binding with its parameters, and nothing else."""

from collections.abc import Callable, Iterable, Sequence
from typing import Literal, Self, final

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

# Arrays the core reads are float64, 1-D unless said otherwise, C-contiguous.
Array = NDArray[np.float64]
Index = NDArray[np.int64]
#: ``progress(step, n_steps, t)`` between blocks of steps (its result is ignored), or None.
Progress = Callable[[int, int, float], object] | None
#: A Python load: the physical load vector (``n_dof``) at time ``t``, or None.
Forcing = Callable[[float], ArrayLike] | None

def transfer(omega: Array, zeta: Array, dt: float, moments: bool = False) -> tuple[Array, Array]:
    """Exact ``A`` (n, 2, 2) and ``B`` (n, 2, 3) — or moments (n, 2, 4) — from natural
    frequencies ``omega`` and damping ratios ``zeta``."""

def transfer_kc(k: Array, c: Array, dt: float, moments: bool = False) -> tuple[Array, Array]:
    """As :func:`transfer`, from modal stiffness ``k = omega^2`` and damping ``c``."""

def mode_bounds(
    pseudo: Array, q: Array, omega: Array, c: Array, step: tuple[float, int, float]
) -> Array:
    """Per mode, the error estimate's accumulated bound of a run (``duhamel._engine.
    accuracy.mode_bounds``): C-contiguous ``(rows, n)`` histories, ``step`` the run's
    ``(h, k, span)``."""

def row_errors(
    pseudo: Array, q: Array, omega: Array, c: Array, signed: Array, step: tuple[float, int, float]
) -> Array:
    """Per row of `signed` ``(g, n)`` (mode shapes with their signs), the error estimate of a
    run there: the modes' local errors carried by their linearised dynamics and combined
    with those shapes, plus the force jumps' errors (``duhamel_core::accuracy::
    row_errors``); histories and ``step`` as for :func:`mode_bounds`."""

def parabola_moments(omega: Array, c: Array, h: float) -> Array:
    """Per mode, the end state ``(q, v)`` of the parabola ``4 s (1 - s)`` over one step
    ``h`` from rest, ``(n, 2)``: the ``DDp`` column of the exact step's load transfer."""

def decaying_max(x: Array, decay: Array) -> Array:
    """Per row of ``x``, the largest value of ``acc_{i+1} = decay acc_i + x_i`` from 0."""

def hold_response(steps: Array, g: Array) -> Array:
    """Per row of `g` ``(n, len)``, ``scale x_k[0]`` of ``x_{k+1} = A x_k + p g_k + r
    g_{k+1}`` from ``x_0 = 0`` with that row of `steps` ``(n, 9)`` = ``(A00, A01, A10, A11,
    p0, p1, r0, r1, scale)``, ``(n, len)``: the basis-truncation estimate's oscillators."""

@final
class Estimator:
    """The error estimate of a prepared modal model's runs: its modes, its mode shapes
    ``phi`` at the saved `dofs` (None: not estimated) and along the elements' deformations
    (per element its dofs and whether it is a two-node element; None: not estimated)."""

    def __new__(
        cls,
        omega: Array,
        c: Array,
        phi: Array,
        dofs: Index | None,
        elements: Sequence[tuple[Sequence[int], bool]] | None,
    ) -> Self: ...
    def estimate(
        self, result: RunResult, h: float, k: int, x: Array, elements: bool
    ) -> tuple[float | None, list[float], float | None, list[float]] | None:
        """``(dofs, elements, dofs_bound, elements_bound)``: the estimates of a whole run,
        then its bounds, or None where one is not a number."""

@final
class SpeedLaw:
    @staticmethod
    def constant(omega: float) -> SpeedLaw: ...
    @staticmethod
    def run_up(omega0: float, omega1: float, t1: float) -> SpeedLaw: ...
    def _to_value(self) -> str:
        """The law as JSON text."""
    @staticmethod
    def _from_value(text: str) -> SpeedLaw: ...
    def evaluate(self, t: Array) -> tuple[Array, Array, Array]:
        """``(omega, omega', theta)`` at the times `t`."""

@final
class TimeFunction:
    @staticmethod
    def step(t0: float) -> TimeFunction: ...
    @staticmethod
    def harmonic(omega: float, phase: float) -> TimeFunction: ...
    @staticmethod
    def table(t: Array, values: Array, hold: bool) -> TimeFunction: ...
    @staticmethod
    def unbalance(law: SpeedLaw, phase: float, axis: Literal["x", "y"]) -> TimeFunction: ...
    @staticmethod
    def misalignment(
        law: SpeedLaw,
        radius: float,
        parallel: tuple[float, float, float],
        angular: tuple[float, float],
        axis: Literal["x", "y"],
    ) -> TimeFunction: ...
    def values(self, t: Array) -> Array:
        """The values at the times `t` (right limits at jumps)."""
    def _to_value(self) -> str:
        """The function as JSON text."""
    @staticmethod
    def _from_value(text: str) -> TimeFunction: ...

@final
class MassLaw:
    @staticmethod
    def exponential(rate: float, scale: float) -> MassLaw: ...
    @staticmethod
    def harmonic(amplitude: float, frequency: float) -> MassLaw: ...
    @staticmethod
    def table(t: Array, mu: Array) -> MassLaw: ...
    def _to_value(self) -> str:
        """The law as JSON text."""
    @staticmethod
    def _from_value(text: str) -> MassLaw: ...

@final
class Mass:
    """The mass of a run: the law ``mu(t)``, the `form` of the inertia term, whether the
    stiffness scales with the mass, and the semi-analytic `treatment` (the direct
    integrators ignore it)."""

    def __new__(
        cls,
        law: MassLaw,
        form: Literal["acceleration", "momentum"],
        scale_stiffness: bool,
        treatment: Literal["eliminate", "estimate"],
    ) -> Self: ...

#: An element function: ``fn(x, v, t) -> r``, or with state ``fn(x, v, t, state) -> (r,
#: trial_state)``.
ElementFunction = Callable[..., ArrayLike | tuple[ArrayLike, ArrayLike]]
#: Its Jacobian ``(dr/dx, dr/dv)`` at ``(x, v, t)`` (and ``state``).
ElementJacobian = Callable[..., tuple[ArrayLike, ArrayLike]]

#: Where an element acts: a dof index or a dof label (a name, or a ``(node, component)`` pair).
Dof = int | str | tuple[int, str]
#: A device's dofs: one, or a tuple of them (None for an absent axis).
Dofs = Dof | Sequence[Dof | None]
Matrix2 = Sequence[Sequence[float]] | NDArray[np.float64]

class Element:
    """Base class of the force elements of ``duhamel.elements``: each built-in element is
    defined once in the core (``crates/duhamel-core/src/elements/registry.rs``) and is a
    subclass made from that definition; parameters are attributes."""

    def __getattribute__(self, name: str, /) -> object: ...
    def __eq__(self, value: object, /) -> bool: ...
    def __ne__(self, value: object, /) -> bool: ...
    def __lt__(self, value: object, /) -> bool: ...
    def __le__(self, value: object, /) -> bool: ...
    def __gt__(self, value: object, /) -> bool: ...
    def __ge__(self, value: object, /) -> bool: ...
    def __reduce__(self) -> tuple[object, ...]: ...
    @property
    def parameters(self) -> dict[str, object]:
        """The parameters as given (dof labels kept), in signature order."""
    def replace(self, **changes: object) -> Self: ...
    def __replace__(self, **changes: object) -> Self: ...
    def evaluate(
        self, position: ArrayLike, velocity: ArrayLike | None = None, t: float = 0.0
    ) -> tuple[Array, NDArray[np.float64], NDArray[np.float64]]:
        """``(r, dr/dx, dr/dx')`` of a path-independent element at a local state."""
    @property
    def _path_dependent(self) -> bool: ...
    @property
    def _dofs(self) -> list[int]: ...
    @property
    def _labelled(self) -> bool: ...
    def _resolved(self, resolve: Callable[[object, str], int]) -> Self: ...
    def _validate(self, system: object) -> None: ...
    def _passive(self) -> bool: ...
    def _linear(self) -> tuple[list[int], NDArray[np.float64]] | None: ...
    def _tangent_bound(self) -> tuple[float, float] | None: ...
    def _directions(self) -> list[tuple[int, int | None]]: ...
    def _remainder(self, c0: Array | None = None) -> Element: ...
    def _stored_energy(
        self, u: Sequence[Sequence[float]], f: Sequence[Sequence[float]]
    ) -> list[float]: ...
    def _linear_matrices(self) -> tuple[list[int], NDArray[np.float64], NDArray[np.float64]]: ...
    def _to_value(self) -> str: ...
    @classmethod
    def _from_value(cls, text: str) -> Element: ...

@final
class Bilinear(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        k: float,
        fy: float,
        alpha: float,
        initial_deformation: float = 0.0,
        initial_force: float | None = None,
    ) -> Self: ...

@final
class BoucWen(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        k: float,
        fy: float,
        alpha: float,
        n: float = 1.0,
        beta: float = 0.5,
        gamma: float = 0.5,
    ) -> Self: ...

@final
class BreathingCrack(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        dk_xi: float,
        dk_eta: float = 0.0,
        breathing: Literal["cosine", "switching"] = "cosine",
        speed: float | object = 0.0,
        phase: float = 0.0,
    ) -> Self: ...

@final
class Callable(Element):  # type: ignore[no-redef]  # (after every use of the import)
    def __new__(
        cls,
        dofs: Dofs,
        fn: ElementFunction,
        jacobian: ElementJacobian | None = None,
        state: Sequence[float] | None = None,
    ) -> Self: ...

@final
class Contact(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        clearance: float,
        stiffness: float,
        friction: float = 0.0,
        smoothing: float | None = None,
        velocity_smoothing: float | None = None,
    ) -> Self: ...

@final
class Cubic(Element):
    def __new__(cls, i: Dof, *, k3: float) -> Self: ...

@final
class Damper(Element):
    def __new__(cls, i: Dof, j: Dof | None = None, *, c: float) -> Self: ...

@final
class ElasticMultiLinear(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        strain: Sequence[float],
        stress: Sequence[float],
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class FrictionPendulum(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        radius: float,
        mu: float,
        weight: float,
        yield_displacement: float = 0.00025,
        mu_slow: float | None = None,
        rate: float = 0.0,
        vertical_stiffness: float | None = None,
        contact_area: float | None = None,
        delta_mu: float = 0.0,
        pressure_alpha: float = 0.0,
        initial_axial_force: float | None = None,
    ) -> Self: ...

@final
class Gap(Element):
    def __new__(cls, i: Dof, j: Dof | None = None, *, gap: float, k: float) -> Self: ...

@final
class Hysteretic(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        s1p: float,
        e1p: float,
        s2p: float,
        e2p: float,
        s3p: float | None = None,
        e3p: float | None = None,
        s1n: float,
        e1n: float,
        s2n: float,
        e2n: float,
        s3n: float | None = None,
        e3n: float | None = None,
        pinch_x: float,
        pinch_y: float,
        damage1: float,
        damage2: float,
        beta: float = 0.0,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class IMKBilin(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        Ke: float,
        theta_p_plus: float,
        theta_pc_plus: float,
        theta_u_plus: float,
        My_plus: float,
        Mmax_My_plus: float,
        res_plus: float,
        theta_p_neg: float,
        theta_pc_neg: float,
        theta_u_neg: float,
        My_neg: float,
        Mmax_My_neg: float,
        res_neg: float,
        lambda_s: float,
        lambda_c: float,
        lambda_k: float,
        c_s: float,
        c_c: float,
        c_k: float,
        D_plus: float,
        D_neg: float,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class JournalElement(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        radius: float,
        length: float,
        clearance: float,
        viscosity: float,
        speed: float | object = 0.0,
        k0: Matrix2 | None = None,
        c0: Matrix2 | None = None,
    ) -> Self: ...

@final
class LeadRubberBearing(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        k: float,
        fy: float,
        alpha: float,
        eta: float = 1.0,
        beta: float = 0.5,
        gamma: float = 0.5,
    ) -> Self: ...

@final
class MinMax(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        material: Element,
        min: float = -1e16,
        max: float = 1e16,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class ModIMKPeakOriented(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        K0: float,
        as_plus: float,
        as_neg: float,
        My_plus: float,
        My_neg: float,
        lambda_s: float,
        lambda_c: float,
        lambda_a: float,
        lambda_k: float,
        c_s: float,
        c_c: float,
        c_a: float,
        c_k: float,
        theta_p_plus: float,
        theta_p_neg: float,
        theta_pc_plus: float,
        theta_pc_neg: float,
        res_plus: float,
        res_neg: float,
        theta_u_plus: float,
        theta_u_neg: float,
        D_plus: float,
        D_neg: float,
        n_factor: float = 0.0,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class MultiLinear(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        strain: Sequence[float],
        stress: Sequence[float],
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class Parallel(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        materials: Sequence[Element],
        factors: Sequence[float] | None = None,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class Pinching4(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        ePf1: float,
        ePd1: float,
        ePf2: float,
        ePd2: float,
        ePf3: float,
        ePd3: float,
        ePf4: float,
        ePd4: float,
        eNf1: float | None = None,
        eNd1: float | None = None,
        eNf2: float | None = None,
        eNd2: float | None = None,
        eNf3: float | None = None,
        eNd3: float | None = None,
        eNf4: float | None = None,
        eNd4: float | None = None,
        rDispP: float,
        rForceP: float,
        uForceP: float,
        rDispN: float | None = None,
        rForceN: float | None = None,
        uForceN: float | None = None,
        gK1: float,
        gK2: float,
        gK3: float,
        gK4: float,
        gKLim: float,
        gD1: float,
        gD2: float,
        gD3: float,
        gD4: float,
        gDLim: float,
        gF1: float,
        gF2: float,
        gF3: float,
        gF4: float,
        gFLim: float,
        gE: float,
        dmgType: Literal["energy", "cycle"] = "energy",
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class Polynomial(Element):
    def __new__(cls, i: Dof, *, coefficients: Sequence[float]) -> Self: ...

@final
class Series(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        materials: Sequence[Element],
        max_iter: int = 100,
        tol: float = 1e-10,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class SpeedTableBearing(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        speeds: Sequence[float],
        values: Sequence[Sequence[float]],
        slopes: Sequence[Sequence[float]] | None = None,
        speed: float | object,
        k0: Matrix2,
        c0: Matrix2,
    ) -> Self: ...

@final
class Spring(Element):
    def __new__(cls, i: Dof, j: Dof | None = None, *, k: float, k3: float = 0.0) -> Self: ...

@final
class Steel02(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        fy: float,
        E: float,
        b: float,
        R0: float = 15.0,
        cR1: float = 0.925,
        cR2: float = 0.15,
        a1: float = 0.0,
        a2: float = 1.0,
        a3: float = 0.0,
        a4: float = 1.0,
        sig_init: float = 0.0,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class Takeda(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        strain: Sequence[float],
        stress: Sequence[float],
        strain_neg: Sequence[float] | None = None,
        stress_neg: Sequence[float] | None = None,
        alpha: float = 0.4,
        initial_deformation: float = 0.0,
    ) -> Self: ...

@final
class TripleFrictionPendulum(Element):
    def __new__(
        cls,
        dofs: Dofs,
        *,
        mu: Sequence[float],
        radius: Sequence[float],
        displacement_capacity: Sequence[float],
        weight: float,
        yield_displacement: float = 0.00025,
        vertical_stiffness: float | None = None,
        min_axial_force: float = 0.0,
        initial_axial_force: float | None = None,
    ) -> Self: ...

@final
class ViscousDamper(Element):
    def __new__(
        cls,
        i: Dof,
        j: Dof | None = None,
        *,
        c: float,
        exponent: float = 1.0,
        v0: float = 0.0001,
        brace_stiffness: float | None = None,
    ) -> Self: ...

def _element(cls: type[Element], params: dict[str, object]) -> Element:
    """The element of class `cls` with `params` (pickling)."""

def _shifted(inner: Element, k0: Sequence[float], c0: Sequence[float]) -> Element:
    """`inner` minus ``k0 x + c0 v`` (row-major ``n x n`` at its ``n`` dofs)."""

def element_names() -> list[tuple[str, str]]:
    """The built-in elements' names and signatures."""

def drive_element(element: Element, x: Array, v: Array, t: Array) -> tuple[Array, Array, Array]:
    """Forces and tangents of `element` driven through local states, committed after each."""

@final
class Load:
    """A built-in load ``pattern * time(t)``: a modal pattern for a :class:`ModalModel`, a
    physical one for a :class:`DirectModel`; the pattern must be finite."""

    def __new__(cls, pattern: Array, time: TimeFunction) -> Self: ...
    @property
    def pattern(self) -> Array: ...
    @property
    def time(self) -> TimeFunction: ...

@final
class Matrix:
    @staticmethod
    def dense(a: NDArray[np.float64]) -> Matrix:
        """A square C-contiguous float64 2-D array."""
    @staticmethod
    def csr(n: int, indptr: Index, indices: Index, data: Array) -> Matrix: ...

@final
class Method:
    @staticmethod
    def alpha(alpha_m: float, alpha_f: float, gamma: float, beta: float) -> Method: ...
    @staticmethod
    def hermite(points: int) -> Method: ...

@final
class ScaledCoupling:
    """Matrices scaled by a speed law: the force ``law(t) (K x + C x')`` (physical, in
    :class:`Matrices`) or the modal pseudo-force ``-law(t) (K q + C q')`` (dense, in
    :class:`PseudoForceRoute`)."""

    def __new__(cls, k: Matrix | None, c: Matrix | None, law: SpeedLaw) -> Self: ...

@final
class Grid:
    """The time grid of a run: ``t0 + (step0 + n) dt``, ``n = 0 .. n_steps``, every
    `save_every`-th instant kept, on `threads` worker threads (None: all cores)."""

    def __new__(
        cls,
        t0: float,
        dt: float,
        n_steps: int,
        save_every: int,
        step0: int = 0,
        threads: int | None = None,
    ) -> Self: ...

@final
class RunSpec:
    """One run of a :class:`ModalModel`: its grid and modal state ``q0``, ``v0``; on the
    first-order route the coordinates `eta0` (``Re | Im``); the elements' committed
    variables of a continued run, `element_state`, and its growth guard's bounds,
    `guard_state`; the energy integrals to accumulate, `energy` (pseudo-force route)."""

    def __new__(
        cls,
        grid: Grid,
        q0: Array,
        v0: Array,
        eta0: Array | None = None,
        element_state: Array | None = None,
        guard_state: Array | None = None,
        energy: EnergySpec | None = None,
    ) -> Self: ...

@final
class EnergySpec:
    """The energy integrals a run accumulates: the modal damping matrix, the loads that are
    ground accelerations with their ``Phi^T M r`` rows and ``r^T M r'`` (`base`), the ground
    velocities at the start, the elements' linear parts in the background (``k0``, ``c0``)."""

    def __new__(
        cls,
        damping: Array,
        base: tuple[Index, Array, Array],
        vg0: Array,
        linear: Array,
        back: Array | None = None,
    ) -> Self: ...

@final
class Options:
    """A ``duhamel.Semianalytic``'s step-equation settings, checked when made."""

    def __new__(
        cls,
        scheme: Literal["a", "b", "c", "hermite"],
        quadrature: Literal["trapezoid", "parabolic", "exact"],
        tol: float,
        max_iter: int,
        solver: Literal["auto", "newton", "modal-newton"],
        subdivisions: int,
        growth_limit: float | None = None,
    ) -> Self: ...

@final
class PseudoForceRoute:
    """The uncoupled background with the pseudo-force corrector: force `elements`, constant
    modal couplings (dense, or None), couplings `scaled` by a speed law (none by default)
    and the `mass` law (None: constant mass)."""

    def __new__(
        cls,
        elements: Sequence[Element],
        options: Options,
        coupling_k: Matrix | None = None,
        coupling_c: Matrix | None = None,
        scaled: Sequence[ScaledCoupling] = ...,
        mass: Mass | None = None,
    ) -> Self: ...

@final
class Corrector:
    """The elements' corrector on the first-order background: `back` (``2 r x 2 m``) maps
    ``[Re eta | Im eta]`` to ``[q | q']``; Newton `tol` and `max_iter`; the growth guard's
    `growth_limit` (None: off)."""

    def __new__(
        cls,
        elements: Sequence[Element],
        back: Array,
        tol: float,
        max_iter: int,
        growth_limit: float | None = None,
    ) -> Self: ...

@final
class FirstOrderRoute:
    """A coupled linear background in its first-order modes: eigenvalues and gains
    (``r x m``) as real and imaginary parts, and the elements' `corrector` (None: linear)."""

    def __new__(
        cls,
        lambda_re: Array,
        lambda_im: Array,
        gain_re: Array,
        gain_im: Array,
        corrector: Corrector | None = None,
    ) -> Self: ...

@final
class Outputs:
    """Outputs mapped during a first-order run: `map` (``2 r x n_cols``), `loads`
    (``n_loads x n_cols``)."""

    def __new__(cls, map: Array, loads: Array, n_cols: int) -> Self: ...

@final
class ModalModel:
    """A modal model, checked once: modal stiffness `k` (``omega^2``) and damping `c` per
    unit modal mass, mass-normalised mode shapes `phi` (``n_dof x n_modes``), its loads
    (modal patterns) and its `route` (None: uncoupled oscillators, exactly)."""

    def __new__(
        cls,
        k: Array,
        c: Array,
        phi: NDArray[np.float64],
        loads: Sequence[Load],
        route: FirstOrderRoute | PseudoForceRoute | None = None,
    ) -> Self: ...
    @property
    def n_modes(self) -> int: ...
    @property
    def n_dof(self) -> int: ...
    @property
    def route(self) -> Literal["uncoupled", "first-order", "pseudo-force"]: ...
    def run(
        self,
        run: RunSpec,
        loads: Sequence[Load] | None = None,
        outputs: Outputs | None = None,
        forcing: Forcing = None,
        progress: Progress = None,
    ) -> RunResult:
        """Runs from `run`'s state over its grid; `loads` (not None) replace the model's for
        this run; `outputs` (first-order route) are mapped during it."""

@final
class Matrices:
    """The physical matrices of a direct run: `m`, `k` (scaled with the mass law when it
    says so), `c`, `k_fixed` (never scaled), and couplings `scaled` by a speed law (none by
    default)."""

    def __new__(
        cls,
        m: Matrix,
        k: Matrix,
        c: Matrix | None = None,
        k_fixed: Matrix | None = None,
        scaled: Sequence[ScaledCoupling] = ...,
    ) -> Self: ...

@final
class DirectRun:
    """One direct run: its grid, initial `x0`, `v0` and, optionally, `a0`
    (generalized-alpha; None: from the equation of motion), and the dofs kept; the energy
    integrals to accumulate (an :class:`EnergySpec` without damping matrix)."""

    def __new__(
        cls,
        grid: Grid,
        x0: Array,
        v0: Array,
        out_dofs: Index,
        a0: Array | None = None,
        energy: EnergySpec | None = None,
    ) -> Self: ...

@final
class DirectModel:
    """A model for the direct integrators: `matrices`, force `elements`, `mass` law (None:
    constant), `method`, and the Newton `tol` and `max_iter` of implicit steps."""

    def __new__(
        cls,
        matrices: Matrices,
        elements: Sequence[Element],
        mass: Mass | None,
        method: Method,
        tol: float,
        max_iter: int,
    ) -> Self: ...
    def run(
        self,
        run: DirectRun,
        loads: Sequence[Load],
        forcing: Forcing = None,
        progress: Progress = None,
    ) -> RunResult:
        """Integrates the physical equations over `run`'s grid; `loads` have physical
        patterns."""

@final
class RunError:
    """Why a run stopped early: ``kind`` ("nonfinite", "convergence", "domain", "stiffness",
    "callback", "interrupted"), the core's ``message``, ``time``, ``step`` (the step not completed),
    ``last_good_time``, ``residual`` and ``iterations`` (Newton), and the Python exception
    behind a callback failure or an interruption (``cause``)."""

    @property
    def kind(self) -> str: ...
    @property
    def message(self) -> str: ...
    @property
    def time(self) -> float: ...
    @property
    def step(self) -> int: ...
    @property
    def last_good_time(self) -> float | None: ...
    @property
    def residual(self) -> float | None: ...
    @property
    def iterations(self) -> int | None: ...
    @property
    def cause(self) -> BaseException | None: ...
    def kept_until(self, last_good_time: float | None) -> RunError: ...

@final
class RunResult:
    """A run's history, time-major; what a route does not produce is None."""

    @property
    def t(self) -> Array: ...
    @property
    def q(self) -> Array | None: ...
    @property
    def v(self) -> Array | None: ...
    @property
    def eta(self) -> Array | None: ...
    @property
    def outputs(self) -> Array | None: ...
    @property
    def load_values(self) -> Array | None: ...
    @property
    def forcing(self) -> Array | None: ...
    @property
    def pseudo(self) -> Array | None: ...
    @property
    def x(self) -> Array | None: ...
    @property
    def a(self) -> Array | None: ...
    @property
    def element_x(self) -> Array | None: ...
    @property
    def element_v(self) -> Array | None: ...
    @property
    def element_force(self) -> Array | None: ...
    @property
    def element_widths(self) -> list[int] | None: ...
    @property
    def element_state(self) -> list[float] | None: ...
    @property
    def guard_state(self) -> list[float] | None: ...
    @property
    def energy(self) -> Array | None: ...
    @property
    def newton_iterations(self) -> int: ...
    @property
    def closed_form_steps(self) -> int: ...
    @property
    def factorizations(self) -> int: ...
    @property
    def subdivided_steps(self) -> int: ...
    @property
    def subdivision_depth(self) -> int: ...
    @property
    def loop_time(self) -> float:
        """Seconds in the engine's loop (GIL released), without extraction and conversion."""
    @property
    def error(self) -> RunError | None: ...

def element_stiffness(
    elements: Iterable[Element], x: Array, v: Array, t: float
) -> tuple[Index, Index, Array]:
    """The elements' stiffness ``dr/dx`` at a state, as COO triplets."""

def elastic_spectra(
    records: Sequence[Array],
    dts: Sequence[float],
    periods: Array,
    dampings: Array,
    threads: int | None = None,
    exact: bool = False,
) -> tuple[Array, Array, Array]:
    """Peaks ``(sd, sv, sa)``, each flat ``[record][damping][period]``; with `exact` the
    peaks between the samples too."""

def rotd_peaks(
    pair: tuple[Array, Array],
    dt: float,
    periods: Array,
    dampings: Array,
    n_angles: int,
    threads: int | None = None,
) -> Array:
    """Peak displacement per direction of the two components `pair` (both sampled at `dt`),
    flat ``[damping][period][angle]``."""

def ductility_spectrum(
    acc: Array,
    dt: float,
    periods: Array,
    oscillator: tuple[float, float],
    ductilities: Array,
    threads: int | None = None,
) -> Array:
    """Yield displacements of the bilinear `oscillator` ``(zeta, alpha)`` reaching each
    ductility, flat ``[ductility][period]``."""

def bilinear_peak(
    acc: Array, dt: float, omega: float, zeta: float, alpha: float, uy: float
) -> float:
    """Peak displacement at the samples of one bilinear oscillator."""

def _panic_for_tests(kind: str) -> None:
    """Test only: panics on purpose (``kind`` "here", "detached" with the GIL released,
    "rayon" in a rayon worker, "thread" in a scoped thread), to check that a panic comes out
    as :class:`duhamel.errors.InternalError`."""
