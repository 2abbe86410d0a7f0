"""Type stub of the native module ``duhamel._core`` (Rust, PyO3).

The spec classes are made once, in Python, and checked by the core when made; a run reads
its problem from the attributes of a spec object (``duhamel._engine.plan.ModalSpec``, or the
namespaces built in ``duhamel.solve`` and ``duhamel._engine.direct``) and returns a
:class:`RunResult`. The protocols below (stub only, ``type_check_only``) name the attributes
each run reads. ``tests/test_stub.py`` checks that this stub names every binding with its
parameters, and nothing else.
"""

from collections.abc import Callable, Iterable, Sequence
from typing import Protocol, final, type_check_only

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

@type_check_only
class _LoadTerm(Protocol):
    """One load term ``pattern * time(t)`` (``duhamel._engine.specs.LoadSpec``)."""

    @property
    def pattern(self) -> Array: ...
    @property
    def time(self) -> TimeFunction: ...

@type_check_only
class _ModalProblem(Protocol):
    """The modal problem of every modal route (``duhamel._engine.plan.ModalSpec``); an
    optional ``step0: int`` is the grid point a continued run starts at."""

    @property
    def k(self) -> Array: ...
    @property
    def c(self) -> Array: ...
    @property
    def q0(self) -> Array: ...
    @property
    def v0(self) -> Array: ...
    @property
    def loads(self) -> Iterable[_LoadTerm]: ...
    @property
    def t0(self) -> float: ...
    @property
    def dt(self) -> float: ...
    @property
    def n_steps(self) -> int: ...
    @property
    def save_every(self) -> int: ...
    @property
    def threads(self) -> int | None: ...
    @property
    def phi(self) -> Array:
        """``n_dof x m``: projects `forcing` on the modes."""

@type_check_only
class _FirstOrderModes(Protocol):
    """First-order modes: eigenvalues, gains (``r x m``) and initial coordinates."""

    @property
    def lambda_re(self) -> Array: ...
    @property
    def lambda_im(self) -> Array: ...
    @property
    def gain_re(self) -> Array: ...
    @property
    def gain_im(self) -> Array: ...
    @property
    def eta0_re(self) -> Array: ...
    @property
    def eta0_im(self) -> Array: ...

@type_check_only
class _Outputs(Protocol):
    """Outputs mapped during a first-order run: ``map`` (``2 r x n_cols``), ``loads``
    (``n_loads x n_cols``)."""

    @property
    def map(self) -> Array: ...
    @property
    def loads(self) -> Array: ...
    @property
    def n_cols(self) -> int: ...

@type_check_only
class _FirstOrderNonlinear(Protocol):
    """Elements on the exact first-order background; an optional ``element_state`` (Array
    or None) is what a continued run starts from."""

    @property
    def phi(self) -> Array: ...
    @property
    def elements(self) -> Iterable[Element]: ...
    @property
    def back(self) -> Array: ...
    @property
    def tol(self) -> float: ...
    @property
    def max_iter(self) -> int: ...

@type_check_only
class _Options(Protocol):
    """A ``duhamel.Semianalytic``'s settings (``scheme`` "a" | "b" | "c", ``quadrature``
    "trapezoid" | "parabolic" | "exact", ``solver`` "auto" | "newton" | "modal-newton"); an
    optional ``subdivisions: int`` (default 4)."""

    @property
    def scheme(self) -> str: ...
    @property
    def quadrature(self) -> str: ...
    @property
    def tol(self) -> float: ...
    @property
    def max_iter(self) -> int: ...
    @property
    def solver(self) -> str: ...

@type_check_only
class _Mass(Protocol):
    """A mass law as a run takes it (``duhamel._engine.specs.MassSpec``): ``form`` "acceleration"
    | "momentum", ``treatment`` "eliminate" | "estimate"."""

    @property
    def law(self) -> MassLaw: ...
    @property
    def form(self) -> str: ...
    @property
    def scale_stiffness(self) -> bool: ...
    @property
    def treatment(self) -> str: ...

@type_check_only
class _ScaledModal(Protocol):
    """A modal coupling ``law(t) (k q + c q')`` (``duhamel._engine.specs.ScaledSpec``)."""

    @property
    def k(self) -> Array | None: ...
    @property
    def c(self) -> Array | None: ...
    @property
    def law(self) -> SpeedLaw: ...

@type_check_only
class _PseudoNonlinear(Protocol):
    """The pseudo-force of the uncoupled route: elements, couplings, mass law; an optional
    ``element_state`` (Array or None)."""

    @property
    def phi(self) -> Array: ...
    @property
    def elements(self) -> Iterable[Element]: ...
    @property
    def options(self) -> _Options: ...
    @property
    def coupling_k(self) -> Array | None: ...
    @property
    def coupling_c(self) -> Array | None: ...
    @property
    def scaled(self) -> Iterable[_ScaledModal]: ...
    @property
    def mass(self) -> _Mass | None: ...

@type_check_only
class _ScaledPhysical(Protocol):
    """A physical coupling ``law(t) (K x + C x')``."""

    @property
    def k(self) -> Matrix | None: ...
    @property
    def c(self) -> Matrix | None: ...
    @property
    def law(self) -> SpeedLaw: ...

@type_check_only
class _DirectProblem(Protocol):
    """The physical problem of a direct integrator (``duhamel._engine.direct``)."""

    @property
    def m(self) -> Matrix: ...
    @property
    def k(self) -> Matrix: ...
    @property
    def c(self) -> Matrix | None: ...
    @property
    def k_fixed(self) -> Matrix | None: ...
    @property
    def scaled(self) -> Iterable[_ScaledPhysical]: ...
    @property
    def elements(self) -> Iterable[Element]: ...
    @property
    def loads(self) -> Iterable[_LoadTerm]: ...
    @property
    def mass(self) -> _Mass | None: ...
    @property
    def x0(self) -> Array: ...
    @property
    def v0(self) -> Array: ...
    @property
    def a0(self) -> Array | None: ...
    @property
    def t0(self) -> float: ...
    @property
    def dt(self) -> float: ...
    @property
    def n_steps(self) -> int: ...
    @property
    def save_every(self) -> int: ...
    @property
    def out_dofs(self) -> Index: ...
    @property
    def method(self) -> Method: ...
    @property
    def tol(self) -> float: ...
    @property
    def max_iter(self) -> int: ...

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
    def unbalance(law: SpeedLaw, phase: float, axis: str) -> TimeFunction: ...
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

#: An element function: ``fn(x, v, t) -> r``, or with state ``fn(x, v, t, state) -> (r,
#: trial_state)``.
ElementFunction = Callable[..., ArrayLike | tuple[ArrayLike, ArrayLike]]
#: Its Jacobian ``(dr/dx, dr/dv)`` at ``(x, v, t)`` (and ``state``).
ElementJacobian = Callable[..., tuple[ArrayLike, ArrayLike]]

@final
class Element:
    """A force element of ``duhamel.elements``, checked when made. Two-node elements act
    on ``x_i - x_j`` (``j`` None: to ground)."""

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
        dof_x: int,
        dof_y: int,
        radius: float,
        length: float,
        clearance: float,
        viscosity: float,
        law: SpeedLaw,
    ) -> Element: ...
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
    def bouc_wen(
        i: int,
        j: int | None,
        k: float,
        fy: float,
        alpha: float,
        n: float,
        beta: float,
        gamma: float,
    ) -> Element: ...
    @staticmethod
    def friction_pendulum(
        dof_x: int,
        dof_y: int,
        radius: float,
        mu: float,
        weight: float,
        yield_displacement: float,
    ) -> Element: ...
    @staticmethod
    def viscous_damper(i: int, j: int | None, c: float, exponent: float, v0: float) -> Element: ...
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
class RunError:
    """Why a run stopped early: ``kind`` ("nonfinite", "convergence", "callback",
    "interrupted"), the core's ``message``, ``time``, ``step`` (the step not completed),
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
    def error(self) -> RunError | None: ...

def solve_uncoupled(problem: _ModalProblem, forcing: Forcing, progress: Progress) -> RunResult:
    """Uncoupled modal oscillators, exactly."""

def solve_first_order(
    problem: _ModalProblem,
    modes: _FirstOrderModes,
    outputs: _Outputs | None,
    nonlinear: _FirstOrderNonlinear | None,
    forcing: Forcing,
    progress: Progress,
) -> RunResult:
    """A coupled linear background exactly in its first-order modes (elements, if any, as
    pseudo-forces on it)."""

def solve_pseudo(
    problem: _ModalProblem, nonlinear: _PseudoNonlinear, forcing: Forcing, progress: Progress
) -> RunResult:
    """The uncoupled background with the pseudo-force corrector."""

def solve_direct(problem: _DirectProblem, forcing: Forcing, progress: Progress) -> RunResult:
    """A direct integrator on the physical equations."""

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
) -> tuple[Array, Array, Array]:
    """Peaks ``(sd, sv, sa)``, each flat ``[record][damping][period]``."""

def rotd_peaks(
    first: Array,
    second: Array,
    dt: float,
    periods: Array,
    dampings: Array,
    n_angles: int,
    threads: int | None = None,
) -> Array:
    """Peak displacement per direction, flat ``[damping][period][angle]``."""

def ductility_spectrum(
    acc: Array,
    dt: float,
    periods: Array,
    zeta: float,
    alpha: float,
    ductilities: Array,
    threads: int | None = None,
) -> Array:
    """Yield displacements reaching each ductility, flat ``[ductility][period]``."""

def bilinear_peak(
    acc: Array, dt: float, omega: float, zeta: float, alpha: float, uy: float
) -> float:
    """Peak displacement at the samples of one bilinear oscillator."""

def _panic_for_tests(kind: str) -> None:
    """Test only: panics on purpose (``kind`` "here", "detached" with the GIL released,
    "rayon" in a rayon worker, "thread" in a scoped thread), to check that a panic comes out
    as :class:`duhamel.errors.InternalError`."""
