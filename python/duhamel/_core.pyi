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
(``duhamel._engine.dispatch`` builds these inputs). ``tests/test_stub.py`` checks that this
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

@final
class SpeedLaw:
    @staticmethod
    def constant(omega: float) -> SpeedLaw: ...
    @staticmethod
    def run_up(omega0: float, omega1: float, t1: float) -> SpeedLaw: ...
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

@final
class MassLaw:
    @staticmethod
    def exponential(rate: float, scale: float) -> MassLaw: ...
    @staticmethod
    def harmonic(amplitude: float, frequency: float) -> MassLaw: ...
    @staticmethod
    def table(t: Array, mu: Array) -> MassLaw: ...

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

@final
class Element:
    """A force element of ``duhamel.elements``, checked when made. Two-node elements act
    on ``x_i - x_j`` (``j`` None: to ground)."""

    @property
    def dofs(self) -> list[int]:
        """The global dofs the element acts on, in its local order."""
    @staticmethod
    def polynomial(dof: int, coefficients: Array) -> Element: ...
    @staticmethod
    def spring(i: int, j: int | None, k: float, k3: float) -> Element: ...
    @staticmethod
    def damper(i: int, j: int | None, c: float) -> Element: ...
    @staticmethod
    def contact(
        dof_x: int,
        dof_y: int,
        clearance: float,
        stiffness: float,
        friction: float,
        smoothing: float,
        velocity_smoothing: float,
    ) -> Element: ...
    @staticmethod
    def journal_bearing(
        dofs: tuple[int, int],
        radius: float,
        length: float,
        clearance: float,
        viscosity: float,
        law: SpeedLaw,
    ) -> Element:
        """On the journal's dofs ``(x, y)``."""
    @staticmethod
    def breathing_crack(
        dof_x: int,
        dof_y: int,
        dk_xi: float,
        dk_eta: float,
        breathing: str,
        phase: float,
        law: SpeedLaw,
    ) -> Element:
        """A breathing crack's stiffness loss in the rotating frame."""
    @staticmethod
    def speed_table(
        dof_x: int,
        dof_y: int,
        speeds: Sequence[float],
        values: Sequence[Sequence[float]],
        slopes: Sequence[Sequence[float]] | None,
        law: SpeedLaw,
    ) -> Element: ...
    def evaluate(
        self, x: Array, v: Array, t: float
    ) -> tuple[list[float], list[float], list[float]]:
        """``(r, dr/dx, dr/dx')`` (row-major) of a path-independent element."""
    @staticmethod
    def bilinear(i: int, j: int | None, k: float, fy: float, alpha: float) -> Element: ...
    @staticmethod
    def device(kind: str, args: tuple) -> Element:
        """A device of the binding's ``devices.rs``: ``"triple_friction_pendulum"`` with
        ``(dof_x, dof_y, mu, radius, displacement_capacity, weight, yield_displacement)``
        (``dof_y`` None: uniaxial; the three middle ones each three floats)."""
    @staticmethod
    def bouc_wen(
        i: int,
        j: int | None,
        k: float,
        fy: float,
        alpha: float,
        shape: tuple[float, float, float],
    ) -> Element:
        """The loop's `shape` is ``(n, beta, gamma)``."""
    @staticmethod
    def friction_pendulum(
        dof_x: int,
        dof_y: int | None,
        radius: float,
        mu: float,
        weight: float,
        yield_displacement: float,
        velocity: tuple[float, float] | None = None,
    ) -> Element:
        """Uniaxial when `dof_y` is None; `velocity` = ``(mu_slow, rate)``."""
    @staticmethod
    def lead_rubber(
        dof_x: int,
        dof_y: int | None,
        strength: tuple[float, float, float],
        shape: tuple[float, float, float],
    ) -> Element:
        """``strength = (k, fy, alpha)``, ``shape = (eta, beta, gamma)``."""
    @staticmethod
    def viscous_damper(i: int, j: int | None, c: float, exponent: float, v0: float) -> Element: ...
    @staticmethod
    def friction_pendulum_axial(
        dofs: list[int],
        radius: float,
        mu: float,
        nominal: tuple[float, float],
        kv: float,
        velocity: tuple[float, float] | None = None,
        pressure: tuple[float, float, float] | None = None,
    ) -> Element:
        """`dofs` = ``(dof_x, [dof_y,] dof_z)``; `velocity` = ``(mu_slow, rate)``, `pressure` =
        ``(area, delta_mu, alpha)``."""
    @staticmethod
    def maxwell_damper(
        i: int, j: int | None, law: tuple[float, float, float], kb: float
    ) -> Element: ...
    @staticmethod
    def shifted(inner: Element, k0: Array, c0: Array) -> Element:
        """`inner` minus ``k0 x + c0 v`` (row-major ``n x n`` at its ``n`` dofs)."""
    @staticmethod
    def gap(i: int, j: int | None, gap: float, k: float) -> Element: ...
    @staticmethod
    def callable(
        dofs: Sequence[int],
        func: ElementFunction,
        jacobian: ElementJacobian | None = None,
        state: Sequence[float] | None = None,
    ) -> Element: ...

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
        scheme: Literal["a", "b", "c"],
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

def drive_material(
    kind: str, params: dict[str, float | str], deformation: Array
) -> tuple[Array, Array]:
    """Drives the uniaxial material ``kind`` (``"ModIMKPeakOriented"``, ``"IMKBilin"``,
    ``"Hysteretic"``, ``"Pinching4"``) with the parameters ``params`` (OpenSees' vocabulary)
    from its virgin state through the deformations ``deformation``, committing after each
    (OpenSees' ``testUniaxialMaterial``/``setStrain``): ``(force, tangent)``."""

def _panic_for_tests(kind: str) -> None:
    """Test only: panics on purpose (``kind`` "here", "detached" with the GIL released,
    "rayon" in a rayon worker, "thread" in a scoped thread), to check that a panic comes out
    as :class:`duhamel.errors.InternalError`."""
