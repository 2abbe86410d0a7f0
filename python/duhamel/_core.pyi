"""Type stub of the native module ``duhamel._core`` (Rust, PyO3).

The spec classes are made once, in Python, and checked by the core when made; a run reads
its problem from the attributes of a spec object (``duhamel._solve.plan.ModalSpec``, or the
namespaces built in ``duhamel.solve`` and ``duhamel._direct``) and returns a
:class:`RunResult`.
"""

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__version__: str

Array = NDArray[np.float64]
Progress = Callable[[int, int, float], Any] | None
Forcing = Callable[[float], Array] | None

def transfer(omega: Array, zeta: Array, dt: float, moments: bool = False) -> tuple[Array, Array]:
    """Exact ``A`` (n, 2, 2) and ``B`` (n, 2, 3) — or moments (n, 2, 4) — from natural
    frequencies ``omega`` and damping ratios ``zeta``."""

def transfer_kc(k: Array, c: Array, dt: float, moments: bool = False) -> tuple[Array, Array]:
    """As :func:`transfer`, from modal stiffness ``k = omega^2`` and damping ``c``."""

class SpeedLaw:
    @staticmethod
    def constant(omega: float) -> SpeedLaw: ...
    @staticmethod
    def run_up(omega0: float, omega1: float, t1: float) -> SpeedLaw: ...
    def evaluate(self, t: Array) -> tuple[Array, Array, Array]:
        """``(omega, omega', theta)`` at the times `t`."""

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

class MassLaw:
    @staticmethod
    def exponential(rate: float, scale: float) -> MassLaw: ...
    @staticmethod
    def harmonic(amplitude: float, frequency: float) -> MassLaw: ...
    @staticmethod
    def table(t: Array, mu: Array) -> MassLaw: ...

class Element:
    @staticmethod
    def polynomial(dof: int, coefficients: Array) -> Element: ...
    @staticmethod
    def spring(i: int, j: int | None, k: float, k3: float) -> Element: ...
    @staticmethod
    def damper(i: int, j: int | None, c: float) -> Element: ...
    @staticmethod
    def shifted(inner: Element, k0: NDArray[np.float64], c0: NDArray[np.float64]) -> Element: ...
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
    def callable(
        dofs: Sequence[int], func: Callable[..., Any], jacobian: Callable[..., Any] | None = None
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
    ) -> tuple[list[float], list[float], list[float]]: ...

class Matrix:
    @staticmethod
    def dense(a: NDArray[np.float64]) -> Matrix: ...
    @staticmethod
    def csr(
        n: int, indptr: NDArray[np.int64], indices: NDArray[np.int64], data: Array
    ) -> Matrix: ...

class Method:
    @staticmethod
    def alpha(alpha_m: float, alpha_f: float, gamma: float, beta: float) -> Method: ...
    @staticmethod
    def hermite(points: int) -> Method: ...

class RunError:
    """Why a run stopped early: ``kind`` ("nonfinite", "convergence", "callback",
    "interrupted"), the core's ``message``, ``time``, ``step`` (the step not completed),
    ``last_good_time``, ``residual`` and ``iterations`` (Newton), and the Python exception
    behind a callback failure or an interruption (``cause``)."""

    kind: str
    message: str
    time: float
    step: int
    last_good_time: float | None
    residual: float | None
    iterations: int | None
    cause: BaseException | None
    def kept_until(self, last_good_time: float | None) -> RunError: ...

class RunResult:
    """A run's history, time-major; what a route does not produce is None."""

    t: Array
    q: Array | None
    v: Array | None
    eta: Array | None
    outputs: Array | None
    load_values: Array | None
    forcing: Array | None
    pseudo: Array | None
    x: Array | None
    a: Array | None
    element_x: Array | None
    element_v: Array | None
    element_force: Array | None
    element_widths: list[int] | None
    element_state: list[float] | None
    newton_iterations: int
    closed_form_steps: int
    factorizations: int
    subdivided_steps: int
    subdivision_depth: int
    error: RunError | None

def solve_uncoupled(problem: Any, forcing: Forcing, progress: Progress) -> RunResult:
    """Uncoupled modal oscillators, exactly."""

def solve_first_order(
    problem: Any, modes: Any, outputs: Any, nonlinear: Any, forcing: Forcing, progress: Progress
) -> RunResult:
    """A coupled linear background exactly in its first-order modes (elements, if any, as
    pseudo-forces on it)."""

def solve_pseudo(problem: Any, nonlinear: Any, forcing: Forcing, progress: Progress) -> RunResult:
    """The uncoupled background with the pseudo-force corrector."""

def solve_direct(problem: Any, forcing: Forcing, progress: Progress) -> RunResult:
    """A direct integrator on the physical equations."""

def element_stiffness(
    elements: Sequence[Element], x: Array, v: Array, t: float
) -> tuple[NDArray[np.int64], NDArray[np.int64], Array]:
    """The elements' stiffness ``dr/dx`` at a state, as COO triplets."""

def elastic_spectra(
    records: list[Array],
    dts: list[float],
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
