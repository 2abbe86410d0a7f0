"""Property-based tests (hypothesis) of duhamel's robustness contract.

The contract
------------
For every input to the public constructors (``System``, the loads, elements, mass and speed
laws, the integrators, the rotor components) and to ``solve`` and
``oscillator.transfer_matrices``/``transfer_moments``, the call either

* returns finite results: every array of a ``Solution`` (``t``, ``x``, ``v``, ``a``) is
  finite, ``t`` strictly increasing, the shapes agree; the step matrices are finite; or
* raises one of the documented exceptions:

  - ``ValueError`` or ``TypeError`` whose message names the parameter (a backticked name
    such as ```dt```, or the parameter's name);
  - ``duhamel.SolverError`` (``reason`` one of "nonfinite", "convergence", "callback")
    whose ``partial`` history is finite (``t``, ``x``, ``v``, ``a``) with ``partial.t``
    strictly increasing, and whose ``time`` is finite;
  - another ``duhamel.errors.DuhamelError``;
  - ``FloatingPointError`` when the accelerations of a successful run overflow (raised when
    ``Solution.a`` is read);
  - the user's own exception from a ``progress`` function (documented: re-raised, with
    ``.partial``).

Never a crash, a hang, NaN or inf returned silently, or another exception type
(``OverflowError``, ``ZeroDivisionError``, ``IndexError``, ``KeyError``, ``AttributeError``,
``AssertionError``, ``numpy.linalg.LinAlgError``, scipy's ARPACK errors, a plain
``RuntimeError``, pyo3's ``PanicException`` ...).

Inputs
------
Extreme and wrong scalars (0, negatives, NaN, inf, 5e-324, +-1e300, ``2**64``, numpy scalars
of every width, bools, strings, None, complex numbers, Fractions and Decimals), arrays of
wrong shapes and dtypes, matrices (random symmetric positive definite, indefinite, singular,
asymmetric, badly scaled, scipy.sparse), Python load and element functions with bad returns,
and random but valid models run on every route (uncoupled, first-order, pseudo-force, the
direct integrators). Every run is tiny: a few dofs and a bounded number of steps
(``t_end = t0 + n dt`` with small ``n``, or a generated ``t_end`` whose step count is either
small or refused before the run).

The input space is split so that the defects found so far do not hide the rest of it:

* each property runs on the **ordinary** domain (physical quantities from 1e-8 to 1e8,
  start times near zero) and, as ``*_extreme``, on the **extreme** one (1e+-150, 1e+-300,
  start times up to 2**64);
* integers beyond the float range (``10**400``) and ragged nested sequences are given to
  every parameter, one call each (``test_huge_integers_are_refused``,
  ``test_ragged_sequences_are_refused``).

The defects this suite found are listed in ``DEFECTS``, all fixed; their minimal failing
inputs are regression tests (``test_former_defect``, ``test_huge_integers_are_refused``,
``test_ragged_sequences_are_refused``). Every property, ordinary and extreme, must pass.

Profiles
--------
``DUHAMEL_HYPOTHESIS_PROFILE`` selects the hypothesis profile of this file:

* ``ci`` (default): about 3,750 examples in all, ``derandomize=True`` and no example
  database, so every run (CI included) tries the same examples; under a minute on two
  cores.
* ``long``: about 61,000 examples, random (a failure prints the ``@reproduce_failure``
  blob to replay it):
  ``DUHAMEL_HYPOTHESIS_PROFILE=long pytest tests/robustness/test_properties.py``.

Every example runs under a time guard: a soft limit (``SIGALRM``, an error naming the
example) and a hard one (``faulthandler`` dumps every thread's stack and ends the process)
for a hang inside native code that never returns to the interpreter.
"""

from __future__ import annotations

import contextlib
import faulthandler
import math
import os
import re
import signal
import sys
import warnings
from collections.abc import Callable, Iterator
from decimal import Decimal
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import HealthCheck, Phase, assume, given, note, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel import mass as MS
from duhamel import speed as S
from duhamel.oscillator import transfer_matrices, transfer_moments

# --------------------------------------------------------------------------------------------
# Profiles and time guard
# --------------------------------------------------------------------------------------------

#: Examples per unit of test weight; the weights below add up to 41.7 (8.2 of them for the
#: modules of issue 24: records, spectra, devices, ensembles, stores, rotors).
_UNIT = {"ci": 90, "long": 1470}
_PROFILE = os.environ.get("DUHAMEL_HYPOTHESIS_PROFILE", "ci")
if _PROFILE not in _UNIT:
    raise ValueError(f"DUHAMEL_HYPOTHESIS_PROFILE must be one of {sorted(_UNIT)}, got {_PROFILE!r}")
_COMMON: dict[str, Any] = {
    "deadline": None,
    "database": None,
    "print_blob": True,
    # No "explain" phase: it replays a failure hundreds of times for its comments.
    "phases": [Phase.explicit, Phase.reuse, Phase.generate, Phase.target, Phase.shrink],
    "suppress_health_check": [
        HealthCheck.too_slow,
        HealthCheck.filter_too_much,
        HealthCheck.data_too_large,
    ],
}
settings.register_profile("duhamel-ci", max_examples=_UNIT["ci"], derandomize=True, **_COMMON)
settings.register_profile("duhamel-long", max_examples=_UNIT["long"], derandomize=False, **_COMMON)


def budget(weight: float) -> settings:
    """The settings of a test: this file's profile, with `weight` units of examples."""
    parent = settings.get_profile(f"duhamel-{_PROFILE}")
    return settings(parent, max_examples=max(1, round(weight * _UNIT[_PROFILE])))


#: Library defects this suite found, all fixed; their minimal cases are in
#: ``test_former_defect`` (regression tests).
DEFECTS = {
    "D1": "an integer beyond the float range leaks OverflowError from every real-number "
    "parameter (duhamel._engine.validate._real_scalar, loads._finite: float(10**400))",
    "D2": "scipy's ArpackError leaks from System.modal (sparse shift-invert) at extreme scales",
    "D3": "numpy/scipy errors leak from System.modal and the direct integrators' eigenvalue "
    "estimate at extreme scales: LinAlgError, ValueError('array must not contain infs or "
    "NaNs'), ValueError('zero-size array to reduction operation maximum')",
    "D4": "System.modal returns non-finite mode shapes or modal damping without an error "
    "(zeta = 5.6e307, rayleigh beta = 1e150 with omega^2 = 2e158; M = 1e-300 I: NaN mode "
    "shapes, and LAPACK prints 'DLASCL parameter number 4 had an illegal value')",
    "D5": "a finished semi-analytic run returns inf in x or v (the physical outputs overflow "
    "while the modal coordinates are finite) instead of SolverError(reason='nonfinite')",
    "D6": "CubicHermite: accelerations that overflow are returned as inf (Solution.a of a "
    "finished run without FloatingPointError; SolverError.partial.a)",
    "D7": "a step below the resolution of t0 (t0 = 1e9, dt = 1e-9) gives a time axis that is "
    "not strictly increasing (Solution.t and SolverError.partial.t)",
    "D8": "Bearing's cubic law divides by x_stat**2: OverflowError or ZeroDivisionError for "
    "extreme x_stat or static deflections",
    "D9": "numpy/scipy errors leak from Rotor.system at extreme shaft and bearing values: "
    "LinAlgError, ValueError('array must not contain infs or NaNs') (kyy = 1.797e308)",
    "D10": "a ragged omega or zeta (transfer_matrices, transfer_moments, System's zeta) leaks "
    "numpy's unnamed ValueError",
    "D11": "speed laws return inf for a finite time (theta = omega t overflows)",
    "D12": "CentralDifference with a mass law that decays to 0 over the run leaks "
    "ZeroDivisionError (stability limit: K / mu_min) instead of the other integrators' "
    "ValueError('`mass law` reaches 0')",
    "D13": "a store whose checkpoint slot's zarr.json is damaged leaks JSONDecodeError or "
    "UnicodeDecodeError from resume (the slot is now treated as damaged and written anew)",
    "D14": "Rotor.critical_speeds on a grid reaching 1e300 rad/s leaks LinAlgError",
    "D15": "Rotor.critical_speeds(harmonic=2) on [0, 1e6] returns a speed where the followed "
    "branch jumps between modes as a crossing (|f - 2 w| = 585 rad/s there)",
}


#: Integers beyond the float range (``float()`` of them overflows): test_huge_integers.
HUGE_INTS = [10**400, -(10**400), 2**1024]
#: A ragged nested sequence (numpy cannot make an array of it): test_ragged_sequences.
RAGGED = [[1.0], [1.0, 2.0]]

#: Seconds an example may take before it fails as a hang (soft: the interpreter is reached
#: between blocks of steps) and before the process is ended with a stack dump (hard).
SOFT_LIMIT = 20.0
HARD_LIMIT = 120.0


class Hang(Exception):
    """An example that ran past the soft time limit."""


@contextlib.contextmanager
def time_limit() -> Iterator[None]:
    """Fails the example after SOFT_LIMIT seconds; ends the process after HARD_LIMIT."""
    if not hasattr(signal, "setitimer"):  # pragma: no cover - not POSIX
        yield
        return

    def alarm(signum: int, frame: Any) -> None:
        raise Hang(f"the example ran longer than {SOFT_LIMIT:g} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, SOFT_LIMIT)
    faulthandler.dump_traceback_later(HARD_LIMIT, exit=True)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)
        faulthandler.cancel_dump_traceback_later()


# --------------------------------------------------------------------------------------------
# The contract
# --------------------------------------------------------------------------------------------

REASONS = {"nonfinite", "convergence", "callback", "stiffness", "growth", "domain"}


class _NoInternalError(Exception):
    """Stands for duhamel.errors.InternalError where the library has none."""


INTERNAL: type[BaseException] = getattr(duhamel.errors, "InternalError", _NoInternalError)
BACKTICKED = re.compile(r"`[^`\s][^`]*`")


class UserStop(Exception):
    """Raised by a generated progress function: documented to come back as it is."""


class UserError(Exception):
    """Raised by a generated load or element function."""


def _chain(exc: BaseException) -> Iterator[BaseException]:
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        yield exc
        exc = exc.__cause__ or exc.__context__  # type: ignore[assignment]


def _describe(exc: BaseException) -> str:
    kind = type(exc)
    return f"{kind.__module__}.{kind.__qualname__}: {exc}"


def check_named(exc: BaseException, names: tuple[str, ...]) -> None:
    """A ValueError/TypeError must name its parameter."""
    msg = str(exc)
    assert BACKTICKED.search(msg) or any(n and n in msg for n in names), (
        f"{type(exc).__name__} does not name the parameter (expected a `name` or one of "
        f"{names}): {msg!r}"
    )


def _strictly_increasing(t: np.ndarray) -> bool:
    return bool(np.all(np.diff(t) > 0))


def check_history(sol: Any, what: str, *, complete: bool) -> None:
    """Finite t, x, v, a with consistent shapes, t strictly increasing."""
    assert isinstance(sol, duhamel.Solution), f"{what} is a {type(sol).__name__}"
    t, x, v = np.asarray(sol.t), np.asarray(sol.x), np.asarray(sol.v)
    n = t.shape[0]
    n_out = np.asarray(sol.dofs).shape[0]
    assert t.ndim == 1, f"{what}.t has shape {t.shape}"
    assert x.shape == (n, n_out) and v.shape == (n, n_out), (
        f"{what}: t {t.shape}, x {x.shape}, v {v.shape}, dofs {n_out}"
    )
    assert np.all(np.isfinite(t)), f"{what}.t is not finite: {t}"
    assert _strictly_increasing(t), f"{what}.t is not strictly increasing: {t}"
    assert np.all(np.isfinite(x)), f"{what}.x has NaN/inf: {x}"
    assert np.all(np.isfinite(v)), f"{what}.v has NaN/inf: {v}"
    if complete:
        assert n >= 2, f"{what}: a finished run saved {n} instants"
        try:
            a = np.asarray(sol.a)
        except FloatingPointError as exc:
            # Documented: the accelerations of a successful run overflow (|x| finite).
            check_named(exc, ("accelerations",))
            return
    else:
        a = np.asarray(sol.a)
    assert a.shape == x.shape, f"{what}: a {a.shape} against x {x.shape}"
    assert np.all(np.isfinite(a)), f"{what}.a has NaN/inf: {a}"
    check_modal(sol, what)


def check_modal(sol: Any, what: str) -> None:
    """The modal history of a semi-analytic run is finite too (docs/errors.md)."""
    modal = sol.modal
    if modal is None:
        return
    for name in ("q", "v", "p", "pseudo_force", "a"):
        try:
            value = np.asarray(getattr(modal, name))
        except FloatingPointError as exc:  # as Solution.a: an overflow named
            check_named(exc, ("accelerations", "overflow"))
            continue
        assert np.all(np.isfinite(value)), f"{what}.modal.{name} has NaN/inf: {value}"


def check_solver_error(err: duhamel.SolverError) -> None:
    for link in _chain(err):
        if isinstance(link, Hang):
            raise AssertionError(f"hang: {link}") from err
    assert err.reason in REASONS, f"undocumented SolverError.reason {err.reason!r}: {err}"
    assert isinstance(err.time, float) and math.isfinite(err.time), f"time {err.time!r}"
    # Documented as counting from 1; a failure at the initial state reports step 0.
    assert err.step is None or (isinstance(err.step, int) and err.step >= 0), err.step
    check_history(err.partial, "SolverError.partial", complete=False)


def contract(call: Callable[[], Any], names: tuple[str, ...] = ()) -> Any:
    """Runs `call` under the contract; returns its result, or None when it was refused with
    a documented exception (checked)."""
    with warnings.catch_warnings(), time_limit():
        warnings.simplefilter("ignore")
        try:
            return call()
        except np.linalg.LinAlgError as exc:  # a ValueError, but numpy's own
            raise AssertionError(f"undocumented exception {_describe(exc)}") from exc
        except (ValueError, TypeError) as exc:
            check_named(exc, names)
        except duhamel.SolverError as exc:
            check_solver_error(exc)
        except INTERNAL as exc:  # a panic in the engine: documented as always a bug
            raise AssertionError(f"internal error (a panic) {_describe(exc)}") from exc
        except duhamel.DuhamelError:
            pass
        except UserStop as exc:
            partial = getattr(exc, "partial", None)
            if partial is not None:
                check_history(partial, "UserStop.partial", complete=False)
        except Hang as exc:
            raise AssertionError(f"hang: {exc}") from exc
        except (KeyboardInterrupt, SystemExit):
            raise
        except BaseException as exc:  # what the contract forbids
            raise AssertionError(f"undocumented exception {_describe(exc)}") from exc
    return None


def run(
    system: Any, integrator: Any, names: tuple[str, ...] = (), **kwargs: Any
) -> duhamel.Solution | None:
    """``duhamel.solve`` under the contract; a finished run's history is checked."""
    sol = contract(lambda: duhamel.solve(system, integrator, **kwargs), names)
    if sol is not None:
        with warnings.catch_warnings(), time_limit():
            warnings.simplefilter("ignore")
            try:
                check_history(sol, "Solution", complete=True)
            except (AssertionError, KeyboardInterrupt, SystemExit):
                raise
            except BaseException as exc:
                raise AssertionError(f"reading the Solution raised {_describe(exc)}") from exc
    return sol


def construct(call: Call) -> Any:
    """A constructor call under the contract: the object, or None when refused."""
    return contract(call, call.names)


def _show(value: Any) -> str:
    """A short repr for the failing examples hypothesis prints."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**20:
        sign = "-" if value < 0 else ""
        return f"{sign}int(~2**{abs(value).bit_length() - 1})"
    if isinstance(value, np.ndarray):
        return f"np.array({np.array2string(value, threshold=20, separator=', ')}, {value.dtype})"
    if sp.issparse(value):
        return f"{type(value).__name__}({_show(value.toarray())})"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k!r}: {_show(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple) and len(value) <= 8:
        inner = ", ".join(_show(v) for v in value)
        return (
            f"[{inner}]"
            if isinstance(value, list)
            else f"({inner}{',' if len(value) == 1 else ''})"
        )
    return repr(value)


class Call:
    """A generated constructor call; its repr is the call as written, for failing examples."""

    def __init__(self, names: tuple[str, ...], fn: Callable[..., Any], *args: Any, **kwargs: Any):
        self.names, self.fn, self.args, self.kwargs = names, fn, args, kwargs

    def __call__(self) -> Any:
        return self.fn(*self.args, **self.kwargs)

    def __repr__(self) -> str:
        parts = [_show(a) for a in self.args] + [f"{k}={_show(v)}" for k, v in self.kwargs.items()]
        return f"{getattr(self.fn, '__qualname__', self.fn)}({', '.join(parts)})"


def not_a_load(value: Any) -> Any:
    return value


def not_an_element(value: Any) -> Any:
    return value


def not_a_law(value: Any) -> Any:
    return value


CONTACT_NAMES = (
    "dof_x",
    "dof_y",
    "clearance",
    "stiffness",
    "friction",
    "smoothing",
    "velocity_smoothing",
)


# --------------------------------------------------------------------------------------------
# Strategies: scalars
# --------------------------------------------------------------------------------------------

NASTY_FLOATS = [
    0.0,
    -0.0,
    -1.0,
    math.nan,
    math.inf,
    -math.inf,
    5e-324,
    -5e-324,
    2.2250738585072014e-308,
    1e-300,
    1e300,
    -1e300,
    1.7976931348623157e308,
]
NASTY_OTHER: list[Any] = [
    2**53 + 1,
    2**64,
    -(2**64),
    True,
    False,
    None,
    "1.0",
    "",
    b"1",
    1 + 2j,
    complex(math.nan, 0.0),
    np.int64(3),
    np.int64(-3),
    np.uint64(2**64 - 1),
    np.int8(-128),
    np.float32(0.1),
    np.float32(3e38),
    np.float16(65504),
    np.float16(math.inf),
    np.float16(math.nan),
    np.longdouble("1e4000"),
    np.complex128(1.0),
    np.bool_(True),
    np.array(1.0),
    np.array([1.0]),
    np.array(math.nan),
    [1.0],
    (),
    Fraction(1, 3),
    Decimal("1.5"),
    Decimal("nan"),
    object(),
]

nasty_scalars = st.one_of(
    st.sampled_from(NASTY_FLOATS),
    st.sampled_from(NASTY_OTHER),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(width=32).map(np.float32),
    st.floats(width=16).map(np.float16),
)


def mostly(good: st.SearchStrategy, bad: st.SearchStrategy, odds: int = 5) -> Any:
    """`good` with probability odds/(odds + 1), else `bad` (shrinks towards `good`)."""
    return st.integers(0, odds).flatmap(lambda i: bad if i == odds else good)


def scalar(good: st.SearchStrategy, odds: int = 5) -> Any:
    return mostly(good, nasty_scalars, odds)


def floats(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def _times(scale: float, x: float) -> float:
    return scale * x


class Domain:
    """The strategies of physical quantities in one input domain: ordinary scales (1e-8 to
    1e8) or extreme ones (up to 1e+-300, start times far from zero)."""

    def __init__(self, name: str, scale_list: list[float], starts: list[float]) -> None:
        self.name = name
        self.scales = st.sampled_from(scale_list)
        #: Any sign, of every scale.
        self.magnitudes = st.builds(_times, self.scales, floats(-10.0, 10.0))
        #: Positive, of every scale.
        self.positives = st.builds(_times, self.scales, floats(1e-3, 10.0))
        #: Start times of runs and records.
        self.starts = st.sampled_from(starts)

    def __repr__(self) -> str:
        return self.name.upper()


ORDINARY = Domain("ordinary", [1.0, 1.0, 1e-3, 1e3, 1e-8, 1e8], [0.0, 0.0, 1.0, -3.0, 10.0])
EXTREME = Domain(
    "extreme", [1.0, 1e-8, 1e8, 1e-150, 1e150, 1e-300, 1e300], [0.0, 0.0, 1.0, 1e-300, 1e6]
)
#: Start times where a step can fall below the resolution of the time axis (the extreme
#: domain of ``solve``'s own arguments).
FAR_STARTS = [1e9, -1e9, 1e15, 2.0**64]
#: Step lengths (both domains).
steps = st.sampled_from([1e-9, 1e-6, 1e-3, 0.01, 0.1, 0.5, 1.0, 10.0, 1e3, 1e6])


# --------------------------------------------------------------------------------------------
# Strategies: arrays and matrices
# --------------------------------------------------------------------------------------------


def vectors(n: int, elements: st.SearchStrategy | None = None) -> st.SearchStrategy:
    els = floats(-10.0, 10.0) if elements is None else elements
    return hnp.arrays(np.float64, (n,), elements=els)


def bad_arrays(n: int) -> st.SearchStrategy:
    """Arrays that are not a float vector of length `n`."""
    return st.one_of(
        st.sampled_from(
            [
                np.zeros(n + 1),
                np.zeros(max(n - 1, 0)),
                np.zeros((n, 1)),
                np.zeros((1, n)),
                np.zeros((n, n)),
                np.full(n, math.nan),
                np.full(n, math.inf),
                np.full(n, 1e308),
                np.full(n, 5e-324),
                np.ones(n, dtype=bool),
                np.ones(n, dtype=complex),
                np.array(["1.0"] * n),
                np.array([object()] * n, dtype=object),
                np.ones(n, dtype=np.float16),
                np.ones(n, dtype=np.int8),
                np.arange(n, dtype=np.uint64),
                np.ones(2 * n)[::2],
                [1.0] * n,
                [[1.0]] * n,
                "abc",
                None,
                1.0,
                [],
                {},
            ]
        ),
        nasty_scalars,
        hnp.arrays(
            hnp.floating_dtypes() | hnp.integer_dtypes(),
            hnp.array_shapes(min_dims=0, max_dims=3, max_side=4),
        ),
    )


def chain(n: int, k: float) -> np.ndarray:
    """Stiffness of a chain of n masses joined by springs k, the first one to ground."""
    K = np.zeros((n, n))
    K[0, 0] = k
    for i in range(n - 1):
        K[i : i + 2, i : i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return K


@st.composite
def spd(draw: Any, n: int, scale: st.SearchStrategy) -> np.ndarray:
    """A random symmetric positive definite matrix times a scale."""
    a = draw(hnp.arrays(np.float64, (n, n), elements=floats(-3.0, 3.0)))
    d = draw(hnp.arrays(np.float64, (n,), elements=floats(0.05, 3.0)))
    return draw(scale) * (a @ a.T + np.diag(d))


@st.composite
def psd(draw: Any, n: int, scale: st.SearchStrategy) -> np.ndarray:
    """A positive semidefinite matrix: a chain, rank-deficient, zero or SPD."""
    kind = draw(st.sampled_from(["chain", "rank1", "zero", "spd", "free"]))
    s = draw(scale)
    if kind == "chain":
        return chain(n, s)
    if kind == "rank1":
        u = draw(vectors(n))
        return s * np.outer(u, u)
    if kind == "zero":
        return np.zeros((n, n))
    if kind == "free":  # free-free chain: one rigid-body mode
        K = np.zeros((n, n))
        for i in range(n - 1):
            K[i : i + 2, i : i + 2] += s * np.array([[1.0, -1.0], [-1.0, 1.0]])
        return K
    return draw(spd(n, st.just(s)))


@st.composite
def wrong_matrices(draw: Any, n: int, dom: Domain) -> Any:
    """Matrices that break a rule: indefinite, asymmetric, singular, badly scaled,
    non-finite, wrong shape or dtype."""
    kind = draw(
        st.sampled_from(
            [
                "indefinite",
                "asymmetric",
                "singular",
                "badly_scaled",
                "nan",
                "inf",
                "shape",
                "dtype",
                "ragged",
                "scalar",
                "empty",
                "3d",
                "negative_diagonal",
            ]
        )
    )
    if kind == "indefinite":
        m = draw(spd(n, st.just(1.0)))
        return m - (np.max(np.linalg.eigvalsh(m)) + draw(floats(0.0, 2.0))) * np.eye(n) * (
            np.arange(n) == 0
        )
    if kind == "asymmetric":
        m = draw(spd(n, st.just(1.0)))
        m[0, -1] += draw(floats(0.5, 5.0)) if n > 1 else 0.0
        return m if n > 1 else -m
    if kind == "singular":
        u = draw(vectors(n))
        return np.outer(u, u)
    if kind == "badly_scaled":
        spread = [1.0, 1e-10, 1e10] + ([1e-300, 1e300] if dom is EXTREME else [])
        d = draw(hnp.arrays(np.float64, (n,), elements=st.sampled_from(spread)))
        return np.diag(d)
    if kind == "nan":
        m = np.eye(n)
        m[draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1))] = math.nan
        return m
    if kind == "inf":
        m = np.eye(n)
        m[0, 0] = math.inf
        return m
    if kind == "shape":
        return np.eye(n + 1)[:, : draw(st.sampled_from([n, n + 1, 1]))]
    if kind == "dtype":
        return np.eye(n).astype(draw(st.sampled_from([bool, complex, object, str, np.float16])))
    if kind == "ragged":
        return [[1.0] * n] + [[1.0]] * (n - 1) if n > 1 else [[1.0, 2.0]]
    if kind == "scalar":
        return draw(st.sampled_from([1.0, np.float64(2.0), "eye", None, np.eye(n).tolist()]))
    if kind == "empty":
        return np.zeros((0, 0))
    if kind == "3d":
        return np.ones((n, n, 1))
    m = np.eye(n)
    m[-1, -1] = -1.0
    return m


def sparse(draw: Any, m: Any) -> Any:
    """Sometimes a scipy.sparse version of the dense matrix `m`."""
    if not isinstance(m, np.ndarray) or m.ndim != 2 or m.dtype.kind not in "fiub":
        return m
    if m.dtype == np.float16:  # scipy.sparse has no float16
        return m
    how = draw(st.sampled_from(["dense", "dense", "dense", "csr_array", "csr_matrix", "coo"]))
    if how == "csr_array":
        return sp.csr_array(m)
    if how == "csr_matrix":
        return sp.csr_matrix(m)
    if how == "coo":
        return sp.coo_array(m)
    return m


@st.composite
def mass_matrices(draw: Any, n: int, dom: Domain) -> Any:
    m = draw(mostly(spd(n, dom.scales), wrong_matrices(n, dom), odds=4))
    return sparse(draw, m)


@st.composite
def stiffness_matrices(draw: Any, n: int, dom: Domain) -> Any:
    m = draw(mostly(psd(n, dom.scales), wrong_matrices(n, dom), odds=4))
    return sparse(draw, m)


# --------------------------------------------------------------------------------------------
# Strategies: runs
# --------------------------------------------------------------------------------------------

#: Integrators that complete for any well-posed model (CentralDifference may refuse dt).
INTEGRATORS = [
    lambda: duhamel.Semianalytic(),
    lambda: duhamel.Semianalytic(coupling="pseudo-force"),
    lambda: duhamel.Semianalytic(scheme="a", quadrature="parabolic"),
    lambda: duhamel.Semianalytic(scheme="c", quadrature="exact", solver="newton"),
    lambda: duhamel.Semianalytic(modes=1),
    lambda: duhamel.Semianalytic(mass_treatment="estimate"),
    lambda: duhamel.Newmark(),
    lambda: duhamel.HHT(-0.1),
    lambda: duhamel.GeneralizedAlpha(0.5),
    lambda: duhamel.CentralDifference(),
    lambda: duhamel.CentralDifference(allow_unstable=True),
    lambda: duhamel.CubicHermite(),
]
integrators = st.sampled_from(range(len(INTEGRATORS))).map(lambda i: INTEGRATORS[i]())


@st.composite
def runs(draw: Any, n: int, dom: Domain, max_steps: int = 60) -> dict[str, Any]:
    """Keyword arguments of a short valid run: ``t_end = t0 + k dt``, k <= max_steps."""
    dt = draw(steps)
    t0 = draw(dom.starts)
    k = draw(st.integers(1, max_steps))
    out: dict[str, Any] = {"t_end": t0 + k * dt, "dt": dt, "t0": t0}
    if draw(st.booleans()):
        out["x0"] = draw(vectors(n, dom.magnitudes))
    if draw(st.booleans()):
        out["v0"] = draw(vectors(n, dom.magnitudes))
    if draw(st.booleans()):
        out["save_every"] = draw(st.integers(1, 7))
    if n > 1 and draw(st.booleans()):
        out["dofs"] = sorted(draw(st.sets(st.integers(0, n - 1), min_size=1)))
    return out


def _real(value: Any) -> float | None:
    """`value` as a float where Python can make one (None for complex numbers, strings ...)."""
    if isinstance(value, complex | np.complexfloating):
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return float(value)
    except (TypeError, ValueError, OverflowError):
        return None


def bounded(t_end: Any, dt: Any, t0: Any = 0.0, limit: int = 2000) -> None:
    """Rejects runs that would take more than `limit` steps yet be accepted: the engine
    refuses more than 2**53 steps before running, but anything in between really runs."""
    te, d, t_0 = _real(t_end), _real(dt), _real(t0)
    if te is None or d is None or t_0 is None:
        return
    if not (math.isfinite(te) and math.isfinite(d) and math.isfinite(t_0) and d > 0):
        return
    with np.errstate(all="ignore"):
        n = (te - t_0) / d
    assume(not (limit < n < 1.01 * 2.0**53))


# --------------------------------------------------------------------------------------------
# The oscillator kernel
# --------------------------------------------------------------------------------------------

kernel_scalars = scalar(
    st.one_of(
        st.floats(0.0, 1e6),
        st.floats(-1e3, 1e3),
        st.sampled_from([0.0, 1e-8, 1.0, 1e3, 1e8, 1e150, 1e300]),
        st.floats(allow_nan=False, allow_infinity=False),
    ),
    odds=4,
)


@st.composite
def kernel_args(draw: Any) -> Any:
    if draw(st.integers(0, 3)) == 0:
        size = draw(st.integers(1, 4))
        return draw(
            st.one_of(
                hnp.arrays(np.float64, (size,), elements=st.floats(allow_nan=True)),
                hnp.arrays(np.float64, (size,), elements=floats(0.0, 1e4)),
                bad_arrays(size),
            )
        )
    return draw(kernel_scalars)


@budget(3.0)
@given(omega=kernel_args(), zeta=kernel_args(), dt=kernel_scalars, moments=st.booleans())
def test_transfer_matrices_are_finite_or_refused(omega, zeta, dt, moments):
    fn = transfer_moments if moments else transfer_matrices
    out = contract(lambda: fn(omega, zeta, dt), ("omega", "zeta", "dt"))
    if out is not None:
        a, b = out
        assert np.all(np.isfinite(a)) and np.all(np.isfinite(b)), (a, b)


# --------------------------------------------------------------------------------------------
# Speed laws
# --------------------------------------------------------------------------------------------


@st.composite
def speed_laws(draw: Any, dom: Domain) -> Any:
    """A speed law (made under the contract: None if refused), a number, or junk."""
    kind = draw(st.sampled_from(["constant", "runup", "number", "junk"]))
    if kind == "constant":
        w = draw(scalar(dom.magnitudes))
        return construct(Call(("omega",), S.ConstantSpeed, w))
    if kind == "runup":
        w0, w1 = draw(scalar(dom.magnitudes)), draw(scalar(dom.magnitudes))
        t1 = draw(scalar(dom.positives))
        return construct(Call(("omega0", "omega1", "t1"), S.LinearRunUp, w0, w1, t1))
    if kind == "number":
        return draw(scalar(dom.magnitudes))
    return draw(st.sampled_from([None, "fast", [1.0, 2.0], lambda t: t, object()]))


@st.composite
def proper_speed_laws(draw: Any, dom: Domain) -> Any:
    if draw(st.booleans()):
        return S.ConstantSpeed(draw(dom.magnitudes))
    return S.LinearRunUp(draw(dom.magnitudes), draw(dom.magnitudes), draw(dom.positives))


def _speed_law_case(law: Any, t: Any) -> None:
    # Finite times only: NaN in, NaN out is numpy's convention for an evaluation (not a
    # constructor); the question is whether a finite time gives an inf silently.
    for method in (law.omega, law.domega, law.theta):
        out = contract(lambda m=method: m(t), ("t",))
        if out is not None:
            assert np.all(np.isfinite(out)), f"{method.__name__}({t!r}) = {out!r} for {law!r}"


@budget(1.0)
@given(
    law=proper_speed_laws(ORDINARY),
    t=st.one_of(ORDINARY.magnitudes, vectors(3, ORDINARY.magnitudes)),
)
def test_speed_laws_evaluate_finite_or_refuse(law, t):
    _speed_law_case(law, t)


@budget(0.5)
@given(
    law=proper_speed_laws(EXTREME),
    t=st.one_of(EXTREME.magnitudes, vectors(3, EXTREME.magnitudes)),
)
def test_speed_laws_evaluate_finite_or_refuse_extreme(law, t):
    _speed_law_case(law, t)


# --------------------------------------------------------------------------------------------
# System
# --------------------------------------------------------------------------------------------


@st.composite
def damping(draw: Any, n: int, dom: Domain) -> dict[str, Any]:
    kind = draw(st.sampled_from(["none", "zeta", "zetas", "rayleigh", "C", "two"]))
    if kind == "zeta":
        return {"zeta": draw(scalar(st.one_of(floats(-0.5, 2.0), dom.magnitudes)))}
    if kind == "zetas":
        return {"zeta": draw(mostly(vectors(n, floats(-0.5, 2.0)), bad_arrays(n)))}
    if kind == "rayleigh":
        alpha = draw(scalar(st.one_of(floats(-1.0, 10.0), dom.magnitudes)))
        beta = draw(scalar(st.one_of(floats(0.0, 0.1), dom.magnitudes)))
        return {"rayleigh": draw(st.sampled_from([(alpha, beta), [alpha], (alpha, beta, 0.0)]))}
    if kind == "C":
        return {"C": sparse(draw, draw(mostly(psd(n, dom.scales), wrong_matrices(n, dom), odds=4)))}
    if kind == "two":
        return {"zeta": 0.05, "rayleigh": (0.1, 0.0)}
    return {}


def _system_case(data: Any, n: int, dom: Domain) -> None:
    M = data.draw(mass_matrices(n, dom), label="M")
    K = data.draw(stiffness_matrices(n, dom), label="K")
    damp = data.draw(damping(n, dom), label="damping")
    system = contract(lambda: duhamel.System(M, K, **damp), ("M", "K", "C", "zeta", "rayleigh"))
    if system is None:
        return
    modes = data.draw(st.one_of(st.none(), scalar(st.integers(1, n))), label="modal(n_modes)")
    basis = contract(lambda: system.modal(modes), ("modes", "n_modes"))
    if basis is not None:
        for name in ("phi", "omega2", "omega", "c", "zeta"):
            value = getattr(basis, name)
            assert np.all(np.isfinite(value)), f"ModalBasis.{name} = {value!r}"
    amplitude = data.draw(dom.magnitudes, label="step amplitude")
    contract(lambda: system.add_load(L.Step(0, amplitude=amplitude)), ("amplitude",))
    integrator = data.draw(integrators, label="integrator")
    run(system, integrator, **data.draw(runs(n, dom), label="run"))


@budget(3.0)
@given(data=st.data(), n=st.integers(1, 4))
def test_system_constructor_and_solve(data, n):
    _system_case(data, n, ORDINARY)


@budget(1.0)
@given(data=st.data(), n=st.integers(1, 4))
def test_system_constructor_and_solve_extreme(data, n):
    _system_case(data, n, EXTREME)


# --------------------------------------------------------------------------------------------
# solve's own arguments
# --------------------------------------------------------------------------------------------

GYRO = np.array([[0.0, 1.0], [-1.0, 0.0]])
SYSTEMS = {
    "uncoupled": lambda: duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]])),
    "damped": lambda: duhamel.System(np.diag([1.0, 2.0]), np.diag([4.0, 9.0]), zeta=0.05),
    "first-order": lambda: duhamel.System(np.eye(2), np.eye(2)).add(E.LinearCoupling(C=GYRO)),
    "pseudo-force": lambda: duhamel.System(np.eye(2), np.eye(2)).add(E.Cubic(0, k3=1.0)),
    "mass-law": lambda: duhamel.System(np.eye(2), np.eye(2)).set_mass_law(MS.Harmonic(0.2, 1.0)),
    "sparse": lambda: duhamel.System(sp.csr_array(np.eye(2)), sp.csr_array(np.eye(2))),
    "callable-load": lambda: duhamel.System(np.eye(2), np.eye(2)).add_load(
        L.Callable(lambda t: np.array([math.sin(t), 0.0]))
    ),
}


def _progress_record(step: int, total: int, t: float) -> None:
    assert 0 <= step <= total and math.isfinite(t)


def _progress_raise(step: int, total: int, t: float) -> None:
    raise UserStop(f"stop at step {step}")


progress_values = st.sampled_from(
    [None, None, False, True, _progress_record, _progress_raise, 1, "yes", np.True_]
)


def _steps_arg(good: st.SearchStrategy) -> Any:
    return scalar(good, odds=3)


def _far(value: Any) -> bool:
    """A real start time farther than 1e6 from zero (the extreme domain's)."""
    v = _real(value)
    return v is not None and math.isfinite(v) and abs(v) > 1e6


def start_times(dom: Domain) -> st.SearchStrategy:
    """`t0`: the domain's start times or bad values; start times far from zero (where a
    step can fall below the resolution of the time axis) belong to the extreme domain."""
    near = nasty_scalars.filter(lambda v: not _far(v))
    if dom is ORDINARY:
        return mostly(dom.starts, near, odds=3)
    far = st.one_of(st.sampled_from(FAR_STARTS), nasty_scalars.filter(_far))
    return mostly(st.one_of(dom.starts, far), st.one_of(far, near), odds=3)


def _solve_arguments_case(data: Any, which: str, integrator: Any, k: int, dom: Domain) -> None:
    system = SYSTEMS[which]()
    dt = data.draw(_steps_arg(steps), label="dt")
    t0 = data.draw(start_times(dom), label="t0")
    real_t0, real_dt = _real(t0), _real(dt)
    natural = 1.0 if real_t0 is None or real_dt is None else real_t0 + k * real_dt
    t_end = data.draw(_steps_arg(st.just(natural)), label="t_end")
    bounded(t_end, dt, t0)
    kwargs: dict[str, Any] = {"t_end": t_end, "dt": dt, "t0": t0}
    optional = {
        "x0": mostly(vectors(2, dom.magnitudes), bad_arrays(2), odds=2),
        "v0": mostly(vectors(2, dom.magnitudes), bad_arrays(2), odds=2),
        "save_every": scalar(st.integers(1, 10), odds=2),
        "dofs": mostly(
            st.sampled_from([[0], [1], [0, 1], [1, 0], np.array([1], dtype=np.int64)]),
            st.one_of(
                st.sampled_from(
                    [[], [2], [-1], [0, 0], [0.0], [True], "0", [[0]], np.array([0.5]), [None]]
                ),
                nasty_scalars,
            ),
            odds=2,
        ),
        "threads": scalar(st.integers(1, 4), odds=2),
        "progress": progress_values,
    }
    for name, strategy in optional.items():
        if data.draw(st.booleans(), label=f"give {name}"):
            kwargs[name] = data.draw(strategy, label=name)
    run(system, integrator, ("t_end", "dt", "t0", *optional), **kwargs)


@budget(3.0)
@given(
    data=st.data(),
    which=st.sampled_from(sorted(SYSTEMS)),
    integrator=integrators,
    k=st.integers(1, 300),
)
def test_solve_arguments(data, which, integrator, k):
    _solve_arguments_case(data, which, integrator, k, ORDINARY)


@budget(1.0)
@given(
    data=st.data(),
    which=st.sampled_from(sorted(SYSTEMS)),
    integrator=integrators,
    k=st.integers(1, 300),
)
def test_solve_arguments_extreme(data, which, integrator, k):
    _solve_arguments_case(data, which, integrator, k, EXTREME)


def test_wrong_system_and_integrator_are_named():
    for system, integrator in [
        (None, duhamel.Semianalytic()),
        (SYSTEMS["uncoupled"](), None),
        (SYSTEMS["uncoupled"](), duhamel.Semianalytic),
        (np.eye(2), duhamel.Newmark()),
    ]:
        run(system, integrator, ("system", "integrator"), t_end=1.0, dt=0.1)


# --------------------------------------------------------------------------------------------
# Integrators
# --------------------------------------------------------------------------------------------


@st.composite
def integrator_args(draw: Any) -> Any:
    kind = draw(
        st.sampled_from(
            ["Semianalytic", "Newmark", "HHT", "GeneralizedAlpha", "CentralDifference", "Hermite"]
        )
    )
    tol = draw(scalar(st.sampled_from([1e-10, 1e-6, 0.5, 1e-300])))
    max_iter = draw(scalar(st.integers(1, 50)))
    newton = {"tol": tol, "max_iter": max_iter}
    if kind == "Semianalytic":
        choice = {
            "scheme": ["a", "b", "c"],
            "quadrature": ["trapezoid", "parabolic", "exact"],
            "mass_treatment": ["eliminate", "estimate"],
            "solver": ["auto", "newton"],
            "coupling": ["auto", "exact", "pseudo-force"],
        }
        kwargs: dict[str, Any] = {
            name: draw(mostly(st.sampled_from(values), st.sampled_from(["B", "", None, 1])))
            for name, values in choice.items()
        }
        kwargs["modes"] = draw(st.one_of(st.none(), scalar(st.integers(1, 3))))
        return duhamel.Semianalytic, kwargs | newton
    if kind == "Newmark":
        g = draw(scalar(floats(0.0, 1.0)))
        b = draw(scalar(floats(0.0, 0.6)))
        return duhamel.Newmark, {"gamma": g, "beta": b} | newton
    if kind == "HHT":
        return duhamel.HHT, {"alpha": draw(scalar(floats(-0.4, 0.1)))} | newton
    if kind == "GeneralizedAlpha":
        return duhamel.GeneralizedAlpha, {"rho_inf": draw(scalar(floats(-0.1, 1.1)))} | newton
    if kind == "CentralDifference":
        allow = draw(mostly(st.booleans(), st.sampled_from([1, "yes", None, np.True_])))
        return duhamel.CentralDifference, {"allow_unstable": allow} | newton
    points = draw(scalar(st.integers(1, 9)))
    return duhamel.CubicHermite, {"points": points} | newton


@budget(2.0)
@given(data=st.data(), spec=integrator_args(), nonlinear=st.booleans())
def test_integrator_constructors_and_solve(data, spec, nonlinear):
    cls, kwargs = spec
    integrator = construct(Call(tuple(kwargs), cls, **kwargs))
    if integrator is None:
        return
    n = data.draw(st.integers(1, 3), label="n")
    system = duhamel.System(np.eye(n), chain(n, 1.0), zeta=0.02)
    if nonlinear:
        system.add(E.Cubic(0, k3=data.draw(floats(-10.0, 1e3), label="k3")))
    system.add_load(L.Harmonic(n - 1, amplitude=1.0, omega=2.0))
    run(system, integrator, **data.draw(runs(n, ORDINARY), label="run"))


# --------------------------------------------------------------------------------------------
# Loads
# --------------------------------------------------------------------------------------------


@st.composite
def tables(draw: Any, dom: Domain) -> tuple[Any, Any]:
    """(t, values) of a record: valid, or broken."""
    size = draw(st.integers(2, 6))
    start = draw(dom.starts)
    gaps = draw(vectors(size - 1, floats(1e-3, 2.0)))
    t = start + np.concatenate([[0.0], np.cumsum(gaps)])
    values = draw(vectors(size, dom.magnitudes))
    broken = draw(st.integers(0, 5))
    if broken == 1:
        t = t[::-1].copy()
    elif broken == 2:
        t = draw(bad_arrays(size))
    elif broken == 3:
        values = draw(bad_arrays(size))
    elif broken == 4:
        t = np.full(size, t[0])
    return t, values


@st.composite
def load_specs(draw: Any, n: int, dom: Domain) -> Call:
    """A load's constructor call."""
    dof = draw(scalar(st.integers(0, n - 1), odds=6))
    kind = draw(
        st.sampled_from(
            ["Step", "Harmonic", "Tabulated", "BaseAcceleration", "Unbalance", "Callable", "junk"]
        )
    )
    if kind == "Step":
        amp, t0 = draw(scalar(dom.magnitudes)), draw(scalar(dom.magnitudes))
        return Call(("dof", "amplitude", "t0"), L.Step, dof, amp, t0)
    if kind == "Harmonic":
        amp, w, ph = (
            draw(scalar(dom.magnitudes)),
            draw(scalar(dom.magnitudes)),
            draw(scalar(dom.magnitudes)),
        )
        return Call(("dof", "amplitude", "omega", "phase"), L.Harmonic, dof, amp, w, ph)
    if kind == "Tabulated":
        t, values = draw(tables(dom))
        hold = draw(mostly(st.booleans(), st.sampled_from(["no", 1, None, np.True_])))
        return Call(("dof", "t", "values", "hold"), L.Tabulated, dof, t, values, hold)
    if kind == "BaseAcceleration":
        t, values = draw(tables(dom))
        r = draw(mostly(vectors(n, dom.magnitudes), bad_arrays(n)))
        return Call(("direction_vector", "t", "values"), L.BaseAcceleration, r, t, values)
    if kind == "Unbalance":
        dy = draw(scalar(st.integers(0, n - 1), odds=6))
        m_e, phase = draw(scalar(dom.magnitudes)), draw(scalar(dom.magnitudes))
        speed = draw(speed_laws(dom))
        return Call(
            ("dof_x", "dof_y", "m_e", "speed", "phase"), L.Unbalance, dof, dy, m_e, speed, phase
        )
    if kind == "Callable":
        fn = draw(load_functions(n, dom))
        return Call(("fn",), L.Callable, fn)
    junk = draw(st.sampled_from([None, 1.0, "Step", E.Cubic(0, k3=1.0), np.zeros(n)]))
    return Call(("load",), not_a_load, junk)


RETURN_KINDS = [
    "full",
    "list",
    "short",
    "long",
    "column",
    "scalar",
    "none",
    "str",
    "strs",
    "complex",
    "bool",
    "object",
    "float16",
    "bigint",
    "generator",
    "dict",
    "raise",
    "zerodiv",
    "keyerror",
]


def make_return(kind: str, value: float, size: int) -> Any:
    if kind == "full":
        return np.full(size, value)
    if kind == "list":
        return [value] * size
    if kind == "short":
        return np.full(max(size - 1, 0), value)
    if kind == "long":
        return np.full(size + 1, value)
    if kind == "column":
        return np.full((size, 1), value)
    if kind == "scalar":
        return value
    if kind == "none":
        return None
    if kind == "str":
        return "force"
    if kind == "strs":
        return ["1.0"] * size
    if kind == "complex":
        return np.full(size, value + 1j)
    if kind == "bool":
        return np.ones(size, dtype=bool)
    if kind == "object":
        return np.array([object()] * size, dtype=object)
    if kind == "float16":
        with np.errstate(over="ignore"):
            return np.full(size, value, dtype=np.float16)
    if kind == "bigint":
        return [2**70] * size
    if kind == "generator":
        return (value for _ in range(size))
    if kind == "dict":
        return {"x": value}
    if kind == "raise":
        raise UserError("the user's function failed")
    if kind == "zerodiv":
        return 1 / 0
    raise KeyError("missing")


class LoadFunction:
    """A Python load f(t): zeros before `after`, then the generated return."""

    def __init__(self, kind: str, value: float, n: int, after: float) -> None:
        self.kind, self.value, self.n, self.after = kind, value, n, after

    def __call__(self, t: float) -> Any:
        if t < self.after:
            return np.zeros(self.n)
        return make_return(self.kind, self.value, self.n)

    def __repr__(self) -> str:
        return f"LoadFunction(kind={self.kind!r}, value={self.value!r}, after={self.after!r})"


@st.composite
def load_functions(draw: Any, n: int, dom: Domain) -> Any:
    kind = draw(mostly(st.just("full"), st.sampled_from(RETURN_KINDS), odds=2))
    value = draw(st.one_of(dom.magnitudes, st.sampled_from(NASTY_FLOATS)))
    after = draw(st.sampled_from([-math.inf, 0.0, 0.05, 1.0]))
    if draw(st.integers(0, 9)) == 0:
        return draw(st.sampled_from([None, 1.0, "f", np.zeros(n)]))
    return LoadFunction(kind, value, n, after)


def _loads_case(data: Any, n: int, integrator: Any, dom: Domain) -> None:
    system = duhamel.System(np.eye(n), chain(n, data.draw(dom.positives, label="k")), zeta=0.05)
    for i in range(data.draw(st.integers(1, 3), label="loads")):
        call = data.draw(load_specs(n, dom), label=f"load {i}")
        load = construct(call)
        if load is not None:
            contract(lambda ld=load: system.add_load(ld), (*call.names, "load"))
    run(system, integrator, **data.draw(runs(n, dom), label="run"))


@budget(3.0)
@given(data=st.data(), n=st.integers(2, 3), integrator=integrators)
def test_loads_construct_and_run(data, n, integrator):
    _loads_case(data, n, integrator, ORDINARY)


@budget(1.0)
@given(data=st.data(), n=st.integers(2, 3), integrator=integrators)
def test_loads_construct_and_run_extreme(data, n, integrator):
    _loads_case(data, n, integrator, EXTREME)


# --------------------------------------------------------------------------------------------
# Elements
# --------------------------------------------------------------------------------------------


class ElementFunction:
    """A Python element r(x, v, t): a cubic spring, then the generated return past `after`."""

    def __init__(self, kind: str, value: float, size: int, after: float) -> None:
        self.kind, self.value, self.size, self.after = kind, value, size, after

    def __call__(self, x: np.ndarray, v: np.ndarray, t: float) -> Any:
        if t < self.after:
            return np.asarray(x) ** 3
        return make_return(self.kind, self.value, self.size)

    def __repr__(self) -> str:
        return f"ElementFunction(kind={self.kind!r}, value={self.value!r}, after={self.after!r})"


JACOBIAN_KINDS = ["good", "none", "one", "three", "nan", "shape", "complex", "raise", "scalars"]


class Jacobian:
    """A Python element's jacobian(x, v, t) with a generated return."""

    def __init__(self, kind: str, size: int) -> None:
        self.kind, self.size = kind, size

    def __call__(self, x: np.ndarray, v: np.ndarray, t: float) -> Any:
        m = self.size
        if self.kind == "good":
            return 3.0 * np.diag(np.asarray(x) ** 2), np.zeros((m, m))
        if self.kind == "none":
            return None
        if self.kind == "one":
            return np.eye(m)
        if self.kind == "three":
            return np.eye(m), np.eye(m), np.eye(m)
        if self.kind == "nan":
            return np.full((m, m), math.nan), np.zeros((m, m))
        if self.kind == "shape":
            return np.eye(m + 1), np.eye(m)
        if self.kind == "complex":
            return np.eye(m) * 1j, np.eye(m)
        if self.kind == "scalars":
            return 1.0, 0.0
        raise UserError("the user's jacobian failed")

    def __repr__(self) -> str:
        return f"Jacobian({self.kind!r})"


@st.composite
def element_specs(draw: Any, n: int, dom: Domain) -> Call:
    dof = draw(scalar(st.integers(0, n - 1), odds=6))
    kind = draw(
        st.sampled_from(
            [
                "Cubic",
                "Polynomial",
                "Spring",
                "Damper",
                "LinearCoupling",
                "Contact",
                "Callable",
                "junk",
            ]
        )
    )
    if kind == "Cubic":
        k3 = draw(scalar(dom.magnitudes))
        return Call(("dof", "k3"), E.Cubic, dof, k3)
    if kind == "Polynomial":
        coefficients = draw(
            mostly(
                st.lists(dom.magnitudes, min_size=0, max_size=6),
                st.one_of(bad_arrays(3), st.lists(nasty_scalars, max_size=3)),
            )
        )
        return Call(("dof", "coefficients"), E.Polynomial, dof, coefficients)
    if kind in ("Spring", "Damper"):
        j = draw(st.one_of(st.none(), scalar(st.integers(0, n - 1), odds=6)))
        a, b = draw(scalar(dom.magnitudes)), draw(scalar(dom.magnitudes))
        if kind == "Spring":
            return Call(("i", "j", "k", "k3"), E.Spring, dof, j, a, b)
        return Call(("i", "j", "c"), E.Damper, dof, j, abs(a) if isinstance(a, float) else a)
    if kind == "LinearCoupling":

        def matrix() -> Any:
            return draw(
                st.one_of(
                    st.none(),
                    st.builds(lambda s, m: s * m, dom.scales, st.sampled_from([GYRO, -GYRO])).map(
                        lambda m: np.pad(m, ((0, n - 2), (0, n - 2)))
                    ),
                    hnp.arrays(np.float64, (n, n), elements=dom.magnitudes),
                    wrong_matrices(n, dom),
                )
            )

        K, C = matrix(), matrix()
        K, C = sparse(draw, K), sparse(draw, C)
        scale = draw(st.one_of(st.none(), speed_laws(dom)))
        return Call(("K", "C", "scale"), E.LinearCoupling, K=K, C=C, scale=scale)
    if kind == "Contact":
        dy = draw(scalar(st.integers(0, n - 1), odds=6))
        gap, stiff = draw(scalar(dom.positives)), draw(scalar(dom.positives))
        friction = draw(scalar(floats(0.0, 1.0)))
        smooth = draw(st.one_of(st.none(), scalar(dom.positives)))
        vsmooth = draw(st.one_of(st.none(), scalar(dom.positives)))
        return Call(CONTACT_NAMES, E.Contact, dof, dy, gap, stiff, friction, smooth, vsmooth)
    if kind == "Callable":
        dofs = draw(
            mostly(
                st.lists(st.integers(0, n - 1), min_size=1, max_size=n, unique=True),
                st.sampled_from([[], [n], [-1], [0, 0], [0.5], [True], "0", None, [[0]]]),
            )
        )
        size = len(dofs) if isinstance(dofs, list) else 1
        kind_r = draw(mostly(st.just("full"), st.sampled_from(RETURN_KINDS), odds=2))
        value = draw(st.one_of(dom.magnitudes, st.sampled_from(NASTY_FLOATS)))
        after = draw(st.sampled_from([-math.inf, 0.0, 0.05, 1.0]))
        fn = ElementFunction(kind_r, value, size, after)
        jac = draw(
            st.one_of(
                st.none(),
                st.sampled_from(JACOBIAN_KINDS).map(lambda k: Jacobian(k, size)),
                st.just("not callable"),
            )
        )
        return Call(("fn", "dofs", "jacobian"), E.Callable, fn, dofs, jac)
    junk = draw(st.sampled_from([None, 1.0, "Cubic", L.Step(0, amplitude=1.0), np.eye(n)]))
    return Call(("element",), not_an_element, junk)


def _elements_case(data: Any, n: int, integrator: Any, dom: Domain) -> None:
    system = duhamel.System(np.eye(n), chain(n, data.draw(dom.positives, label="k")), zeta=0.02)
    for i in range(data.draw(st.integers(1, 2), label="elements")):
        call = data.draw(element_specs(n, dom), label=f"element {i}")
        element = construct(call)
        if element is not None:
            contract(lambda el=element: system.add(el), (*call.names, "element"))
    system.add_load(L.Step(n - 1, amplitude=data.draw(dom.magnitudes, label="step")))
    run(system, integrator, **data.draw(runs(n, dom), label="run"))


@budget(3.5)
@given(data=st.data(), n=st.integers(2, 3), integrator=integrators)
def test_elements_construct_and_run(data, n, integrator):
    _elements_case(data, n, integrator, ORDINARY)


@budget(1.0)
@given(data=st.data(), n=st.integers(2, 3), integrator=integrators)
def test_elements_construct_and_run_extreme(data, n, integrator):
    _elements_case(data, n, integrator, EXTREME)


# --------------------------------------------------------------------------------------------
# Mass laws
# --------------------------------------------------------------------------------------------


@st.composite
def mass_law_specs(draw: Any, dom: Domain) -> Call:
    kind = draw(st.sampled_from(["Exponential", "Harmonic", "Tabulated", "junk"]))
    if kind == "Exponential":
        rate = draw(scalar(st.one_of(floats(-2.0, 2.0), dom.magnitudes)))
        scale = draw(st.one_of(st.just(1.0), scalar(dom.positives)))
        return Call(("rate", "scale"), MS.Exponential, rate, scale)
    if kind == "Harmonic":
        amp = draw(scalar(floats(-1.0, 1.0)))
        freq = draw(scalar(dom.magnitudes))
        return Call(("amplitude", "frequency"), MS.Harmonic, amp, freq)
    if kind == "Tabulated":
        t, mu = draw(tables(dom))
        if draw(st.booleans()) and isinstance(mu, np.ndarray) and mu.dtype == np.float64:
            mu = np.abs(mu) + draw(dom.positives)
        return Call(("t", "mu"), MS.Tabulated, t, mu)
    junk = draw(st.sampled_from([None, 1.0, "exp", lambda t: 1.0]))
    return Call(("law",), not_a_law, junk)


def _mass_laws_case(data: Any, n: int, integrator: Any, dom: Domain) -> None:
    system = duhamel.System(np.eye(n), chain(n, data.draw(dom.positives, label="k")), zeta=0.02)
    call = data.draw(mass_law_specs(dom), label="mass law")
    law = construct(call)
    if law is None:
        return
    form = data.draw(mostly(st.sampled_from(["acceleration", "momentum"]), nasty_scalars))
    scale_k = data.draw(mostly(st.booleans(), st.sampled_from([1, "no", None, np.False_])))
    attached = contract(
        lambda: system.set_mass_law(law, form=form, scale_stiffness=scale_k),
        (*call.names, "law", "form", "scale_stiffness"),
    )
    if attached is None:
        return
    if data.draw(st.booleans(), label="cubic"):
        system.add(E.Cubic(0, k3=1.0))
    system.add_load(L.Harmonic(0, amplitude=1.0, omega=3.0))
    run(system, integrator, **data.draw(runs(n, dom), label="run"))


@budget(2.5)
@given(data=st.data(), n=st.integers(1, 3), integrator=integrators)
def test_mass_laws_construct_and_run(data, n, integrator):
    _mass_laws_case(data, n, integrator, ORDINARY)


@budget(1.0)
@given(data=st.data(), n=st.integers(1, 3), integrator=integrators)
def test_mass_laws_construct_and_run_extreme(data, n, integrator):
    _mass_laws_case(data, n, integrator, EXTREME)


# --------------------------------------------------------------------------------------------
# Random valid models on every route
# --------------------------------------------------------------------------------------------


class Sine:
    """A Python load ``amplitude sin(t + i)`` on dof i."""

    def __init__(self, amplitude: float, n: int) -> None:
        self.amplitude, self.n = amplitude, n

    def __call__(self, t: float) -> np.ndarray:
        return self.amplitude * np.sin(t + np.arange(self.n))

    def __repr__(self) -> str:
        return f"Sine({self.amplitude!r}, {self.n})"


class CubicForce:
    """A Python element ``k3 x^3``."""

    def __init__(self, k3: float) -> None:
        self.k3 = k3

    def __call__(self, x: np.ndarray, v: np.ndarray, t: float) -> np.ndarray:
        return self.k3 * np.asarray(x) ** 3

    def __repr__(self) -> str:
        return f"CubicForce({self.k3!r})"


@st.composite
def smooth_loads(draw: Any, n: int, dom: Domain) -> Any:
    kind = draw(st.sampled_from(["Step", "Harmonic", "Tabulated", "Base", "Unbalance", "Fn"]))
    dof = draw(st.integers(0, n - 1))
    amp = draw(dom.magnitudes)
    if kind == "Step":
        return L.Step(dof, amplitude=amp, t0=draw(floats(-1.0, 5.0)))
    if kind == "Harmonic":
        return L.Harmonic(
            dof, amplitude=amp, omega=draw(st.one_of(floats(0.0, 100.0), dom.positives))
        )
    if kind in ("Tabulated", "Base"):
        size = draw(st.integers(2, 5))
        t = np.cumsum(draw(vectors(size, floats(1e-3, 1.0)))) - draw(floats(0.0, 1.0))
        values = draw(vectors(size, dom.magnitudes))
        if kind == "Tabulated":
            return L.Tabulated(dof, t=t, values=values, hold=draw(st.booleans()))
        return L.BaseAcceleration(draw(vectors(n, floats(-1.0, 1.0))), t=t, values=values)
    if kind == "Unbalance" and n >= 2:
        law = draw(
            st.one_of(
                floats(-300.0, 300.0),
                st.builds(
                    S.LinearRunUp, floats(-100.0, 100.0), floats(-300.0, 300.0), dom.positives
                ),
            )
        )
        return L.Unbalance((0, 1), m_e=abs(amp), speed=law, phase=draw(floats(-4.0, 4.0)))
    return L.Callable(Sine(amp, n))


@st.composite
def smooth_elements(draw: Any, n: int, dom: Domain) -> Any:
    kind = draw(
        st.sampled_from(["Cubic", "Polynomial", "Spring", "Damper", "Coupling", "Contact", "Fn"])
    )
    dof = draw(st.integers(0, n - 1))
    if kind == "Cubic":
        return E.Cubic(dof, k3=draw(dom.magnitudes))
    if kind == "Polynomial":
        return E.Polynomial(
            dof, coefficients=draw(st.lists(floats(-10.0, 10.0), min_size=1, max_size=6))
        )
    if kind == "Spring":
        j = draw(st.one_of(st.none(), st.integers(0, n - 1).filter(lambda j: j != dof)))
        return E.Spring(dof, j, k=draw(dom.magnitudes), k3=draw(dom.magnitudes))
    if kind == "Damper":
        j = draw(st.one_of(st.none(), st.integers(0, n - 1).filter(lambda j: j != dof)))
        return E.Damper(dof, j, c=abs(draw(dom.magnitudes)))
    if kind == "Coupling" and n >= 2:
        g = np.zeros((n, n))
        g[0, 1], g[1, 0] = 1.0, -1.0
        ks, cs = draw(dom.magnitudes), draw(dom.magnitudes)
        scale = draw(
            st.one_of(
                st.none(),
                floats(-100.0, 100.0),
                st.builds(S.LinearRunUp, floats(-10.0, 10.0), floats(-100.0, 100.0), dom.positives),
            )
        )
        which = draw(st.sampled_from(["K", "C", "both"]))
        K = ks * g if which in ("K", "both") else None
        C = cs * g if which in ("C", "both") else None
        return E.LinearCoupling(K=K, C=C, scale=scale)
    if kind == "Contact" and n >= 2:
        return E.Contact(
            (0, 1),
            clearance=abs(draw(dom.magnitudes)),
            stiffness=draw(dom.positives),
            friction=draw(floats(0.0, 0.5)),
        )
    k3 = draw(floats(-10.0, 100.0))
    return E.Callable([dof], CubicForce(k3))


@st.composite
def models(draw: Any, dom: Domain) -> tuple[Any, int]:
    n = draw(st.integers(1, 4))
    M = draw(
        st.one_of(
            spd(n, dom.scales), hnp.arrays(np.float64, (n,), elements=dom.positives).map(np.diag)
        )
    )
    K = draw(psd(n, dom.scales))
    kind = draw(st.sampled_from(["none", "zeta", "rayleigh", "C"]))
    damp: dict[str, Any] = {}
    if kind == "zeta":
        damp = {"zeta": draw(st.one_of(floats(-0.2, 3.0), vectors(n, floats(-0.2, 3.0))))}
    elif kind == "rayleigh":
        damp = {"rayleigh": (draw(floats(-1.0, 10.0)), draw(floats(0.0, 0.1)))}
    elif kind == "C":
        damp = {"C": draw(psd(n, dom.scales))}
    M, K = sparse(draw, M), sparse(draw, K)
    if "C" in damp:
        damp["C"] = sparse(draw, damp["C"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = contract(lambda: duhamel.System(M, K, **damp), ("M", "K", "C", "zeta"))
    assume(system is not None)
    note(f"System(M={_show(M)}, K={_show(K)}, **{_show(damp)})")
    for _ in range(draw(st.integers(0, 3))):
        load = draw(smooth_loads(n, dom))
        note(f"add_load({load!r})")
        system.add_load(load)
    for _ in range(draw(st.integers(0, 2))):
        element = draw(smooth_elements(n, dom))
        note(f"add({element!r})")
        system.add(element)
    if draw(st.integers(0, 3)) == 0:
        law = draw(
            st.sampled_from(
                [
                    MS.Exponential(-0.1),
                    MS.Exponential(0.5, 2.0),
                    MS.Harmonic(0.3, 5.0),
                    MS.Tabulated([0.0, 1.0, 2.0], [1.0, 0.5, 0.8]),
                ]
            )
        )
        note(f"set_mass_law({law!r})")
        system.set_mass_law(
            law,
            form=draw(st.sampled_from(["acceleration", "momentum"])),
            scale_stiffness=draw(st.booleans()),
        )
    return system, n


def _models_case(data: Any, model: tuple[Any, int], integrator: Any, dom: Domain) -> None:
    system, n = model
    note(repr(system))
    run(system, integrator, **data.draw(runs(n, dom, max_steps=120), label="run"))


@budget(4.0)
@given(data=st.data(), model=models(ORDINARY), integrator=integrators)
def test_random_models_on_every_route(data, model, integrator):
    _models_case(data, model, integrator, ORDINARY)


@budget(1.5)
@given(data=st.data(), model=models(EXTREME), integrator=integrators)
def test_random_models_on_every_route_extreme(data, model, integrator):
    _models_case(data, model, integrator, EXTREME)


# --------------------------------------------------------------------------------------------
# Rotors
# --------------------------------------------------------------------------------------------


@st.composite
def rotor_parts(draw: Any, dom: Domain) -> Any:
    """A small rotor (one or two shafts), its speed and loads; every constructor call is
    made under the contract and shown in failing examples."""
    from duhamel import rotor as R

    def made(call: Call, label: str) -> Any:
        note(f"{label}: {call!r}")
        return construct(call)

    material = made(
        Call(
            ("E", "rho", "G", "nu"),
            R.Material,
            E=draw(scalar(st.just(211e9))),
            rho=draw(scalar(st.just(7810.0))),
            nu=draw(scalar(floats(-0.9, 0.49))),
        ),
        "material",
    )
    assume(material is not None)
    n_shafts = draw(st.integers(1, 2))
    shaft = made(
        Call(
            ("L", "outer_diameter", "inner_diameter", "shear_coefficient"),
            R.Shaft,
            draw(scalar(st.one_of(floats(0.05, 1.0), dom.positives))),
            draw(scalar(st.one_of(floats(0.01, 0.2), dom.positives))),
            draw(st.one_of(st.just(0.0), scalar(floats(0.0, 0.009)))),
            material=material,
            shear_coefficient=draw(st.one_of(st.none(), scalar(floats(0.1, 1.0)))),
        ),
        "shaft",
    )
    assume(shaft is not None)
    disks = []
    if draw(st.booleans()):
        disk = made(
            Call(
                ("node", "mass", "Ip", "Id"),
                R.Disk,
                draw(scalar(st.integers(0, n_shafts), odds=8)),
                draw(scalar(dom.positives)),
                draw(scalar(dom.positives)),
                draw(scalar(dom.positives)),
            ),
            "disk",
        )
        if disk is not None:
            disks.append(disk)
    bearings = []
    for node in (0, n_shafts):
        kxy = draw(st.one_of(st.just(0.0), scalar(dom.magnitudes)))
        cxx = draw(st.one_of(st.just(1e3), scalar(dom.positives)))
        beta = draw(st.one_of(st.just(0.0), scalar(floats(0.0, 0.5))))
        bearing = made(
            Call(
                ("node", "kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "beta", "x_stat", "contact"),
                R.Bearing,
                node,
                kxx=draw(scalar(st.one_of(st.just(1e7), dom.positives))),
                kyy=draw(scalar(st.just(1e7))),
                kxy=kxy,
                kyx=-kxy if isinstance(kxy, float) else kxy,
                cxx=cxx,
                cyy=cxx,
                beta=beta,
                x_stat=draw(st.one_of(st.none(), scalar(dom.positives))) if beta else None,
                contact=draw(
                    st.one_of(st.none(), st.tuples(scalar(dom.positives), scalar(dom.positives)))
                ),
            ),
            f"bearing at node {node}",
        )
        if bearing is not None:
            bearings.append(bearing)
    zeta = draw(st.one_of(st.none(), scalar(floats(0.0, 0.2))))
    rotor = made(Call(("zeta",), R.Rotor, [shaft] * n_shafts, disks, bearings, zeta=zeta), "rotor")
    assume(rotor is not None)
    speed = draw(st.one_of(scalar(floats(-500.0, 500.0)), speed_laws(dom)))
    loads = []
    if draw(st.booleans()):
        loads.append(
            made(
                Call(("node", "m_e"), R.Unbalance, n_shafts, draw(scalar(dom.positives))),
                "unbalance",
            )
        )
    if draw(st.booleans()):
        loads.append(R.Gravity())
    loads = [ld for ld in loads if ld is not None]
    return rotor, speed, loads


def _rotor_case(data: Any, parts: Any) -> None:
    rotor, speed, loads = parts
    system = contract(
        lambda: rotor.system(speed, loads),
        ("speed", "loads", "rho", "mass", "bearings", "shafts", "disks"),
    )
    if system is None:
        return
    integrator = data.draw(
        st.sampled_from(
            [
                lambda: duhamel.Semianalytic(),
                lambda: duhamel.Semianalytic(modes=4),
                lambda: duhamel.Newmark(),
                lambda: duhamel.CubicHermite(),
            ]
        ).map(lambda make: make()),
        label="integrator",
    )
    dt = data.draw(st.sampled_from([1e-6, 1e-4, 1e-3, 0.1]), label="dt")
    k = data.draw(st.integers(1, 30), label="steps")
    run(system, integrator, t_end=k * dt, dt=dt)


@budget(1.0)
@given(data=st.data(), parts=rotor_parts(ORDINARY))
def test_rotors_construct_and_run(data, parts):
    _rotor_case(data, parts)


@budget(0.5)
@given(data=st.data(), parts=rotor_parts(EXTREME))
def test_rotors_construct_and_run_extreme(data, parts):
    _rotor_case(data, parts)


# --------------------------------------------------------------------------------------------
# Integers beyond the float range, ragged sequences: every parameter, one call each
# --------------------------------------------------------------------------------------------


def _one() -> duhamel.System:
    return duhamel.System(np.eye(1), np.eye(1))


def _two() -> duhamel.System:
    return duhamel.System(np.eye(2), np.eye(2))


def _solve(**kwargs: Any) -> Any:
    run_ = {"t_end": 1.0, "dt": 0.1} | kwargs
    return duhamel.solve(_two(), duhamel.Semianalytic(), **run_)


def _rotor() -> Any:
    from duhamel import rotor as R

    return R


#: Every real-number parameter of the public constructors, ``solve`` and the kernel, as a
#: function of the value (name: the parameter the error must name).
REAL_PARAMETERS: dict[str, Callable[[Any], Any]] = {
    "solve(dt)": lambda v: _solve(dt=v),
    "solve(t_end)": lambda v: _solve(t_end=v),
    "solve(t0)": lambda v: _solve(t0=v),
    "solve(save_every)": lambda v: _solve(save_every=v),
    "solve(threads)": lambda v: _solve(threads=v),
    "System(zeta)": lambda v: duhamel.System(np.eye(1), np.eye(1), zeta=v),
    "System(rayleigh)": lambda v: duhamel.System(np.eye(1), np.eye(1), rayleigh=(v, 0.0)),
    "System.modal(n_modes)": lambda v: _one().modal(v),
    "Semianalytic(modes)": lambda v: duhamel.Semianalytic(modes=v),
    "Newmark(gamma)": lambda v: duhamel.Newmark(gamma=v),
    "Newmark(tol)": lambda v: duhamel.Newmark(tol=v),
    "Newmark(max_iter)": lambda v: duhamel.Newmark(max_iter=v),
    "HHT(alpha)": lambda v: duhamel.HHT(v),
    "GeneralizedAlpha(rho_inf)": lambda v: duhamel.GeneralizedAlpha(v),
    "CubicHermite(points)": lambda v: duhamel.CubicHermite(points=v),
    "loads.Step(dof)": lambda v: _one().add_load(L.Step(v, amplitude=1.0)),
    "loads.Step(amplitude)": lambda v: L.Step(0, amplitude=v),
    "loads.Step(t0)": lambda v: L.Step(0, amplitude=1.0, t0=v),
    "loads.Harmonic(omega)": lambda v: L.Harmonic(0, amplitude=1.0, omega=v),
    "loads.Unbalance(m_e)": lambda v: L.Unbalance((0, 1), m_e=v, speed=10.0),
    "loads.Unbalance(phase)": lambda v: L.Unbalance((0, 1), m_e=1.0, speed=10.0, phase=v),
    "loads.Unbalance(speed)": lambda v: L.Unbalance((0, 1), m_e=1.0, speed=v),
    "elements.Cubic(k3)": lambda v: E.Cubic(0, k3=v),
    "elements.Spring(k)": lambda v: E.Spring(0, None, k=v),
    "elements.Damper(c)": lambda v: E.Damper(0, None, c=v),
    "elements.Contact(clearance)": lambda v: E.Contact((0, 1), clearance=v, stiffness=1.0),
    "elements.LinearCoupling(scale)": lambda v: E.LinearCoupling(K=GYRO, scale=v),
    "mass.Exponential(rate)": lambda v: MS.Exponential(v),
    "mass.Harmonic(frequency)": lambda v: MS.Harmonic(0.1, v),
    "speed.ConstantSpeed(omega)": lambda v: S.ConstantSpeed(v),
    "speed.LinearRunUp(t1)": lambda v: S.LinearRunUp(0.0, 1.0, v),
    "transfer_matrices(dt)": lambda v: transfer_matrices(1.0, 0.1, v),
    "transfer_matrices(omega)": lambda v: transfer_matrices(v, 0.1, 0.1),
    "rotor.Material(E)": lambda v: _rotor().Material(E=v, rho=1.0, nu=0.3),
    "rotor.Material(nu)": lambda v: _rotor().Material(E=1.0, rho=1.0, nu=v),
    "rotor.Shaft(L)": lambda v: _rotor().Shaft(v, 0.05, material=_rotor().STEEL),
    "rotor.Disk(mass)": lambda v: _rotor().Disk(0, v, 1.0, 1.0),
    "rotor.Bearing(kxx)": lambda v: _rotor().Bearing(0, kxx=v, kyy=1.0),
    "rotor.Unbalance(m_e)": lambda v: _rotor().Unbalance(0, v),
    "rotor.rpm(value)": lambda v: _rotor().rpm(v),
}


def _parameter(target: str) -> str:
    return target[target.index("(") + 1 : -1]


@pytest.mark.parametrize("target", sorted(REAL_PARAMETERS))
def test_huge_integers_are_refused(target):
    """An integer beyond the float range is a bad value like inf: ValueError or TypeError
    naming the parameter."""
    for value in HUGE_INTS:
        contract(lambda v=value: REAL_PARAMETERS[target](v), (_parameter(target),))


#: Every array parameter, as a function of the value.
ARRAY_PARAMETERS: dict[str, Callable[[Any], Any]] = {
    "System(M)": lambda v: duhamel.System(v, np.eye(2)),
    "System(K)": lambda v: duhamel.System(np.eye(2), v),
    "System(C)": lambda v: duhamel.System(np.eye(2), np.eye(2), C=v),
    "System(zeta)": lambda v: duhamel.System(np.eye(2), np.eye(2), zeta=v),
    "solve(x0)": lambda v: _solve(x0=v),
    "solve(v0)": lambda v: _solve(v0=v),
    "solve(dofs)": lambda v: _solve(dofs=v),
    "loads.Tabulated(t)": lambda v: L.Tabulated(0, t=v, values=[0.0, 1.0]),
    "loads.Tabulated(values)": lambda v: L.Tabulated(0, t=[0.0, 1.0], values=v),
    "loads.BaseAcceleration(direction_vector)": lambda v: L.BaseAcceleration(
        v, t=[0, 1], values=[0, 1]
    ),
    "elements.Polynomial(coefficients)": lambda v: E.Polynomial(0, coefficients=v),
    "elements.LinearCoupling(K)": lambda v: E.LinearCoupling(K=v),
    "elements.Callable(dofs)": lambda v: E.Callable(v, CubicForce(1.0)),
    "mass.Tabulated(mu)": lambda v: MS.Tabulated([0.0, 1.0], v),
    "transfer_matrices(omega)": lambda v: transfer_matrices(v, 0.1, 0.1),
    "transfer_matrices(zeta)": lambda v: transfer_matrices(1.0, v, 0.1),
    "transfer_moments(omega)": lambda v: transfer_moments(v, 0.1, 0.1),
    "rotor.Bearing(speeds)": lambda v: _rotor().Bearing(0, kxx=[1.0, 2.0], kyy=1.0, speeds=v),
}


@pytest.mark.parametrize("target", sorted(ARRAY_PARAMETERS))
def test_ragged_sequences_are_refused(target):
    contract(lambda: ARRAY_PARAMETERS[target](RAGGED), (_parameter(target),))


# --------------------------------------------------------------------------------------------
# The defects found, each as its minimal failing input (fixed: regression tests)
# --------------------------------------------------------------------------------------------

CHAIN3 = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
CHAIN2 = np.array([[2.0, -1.0], [-1.0, 1.0]])


def _modal(system_args: tuple, kwargs: dict | None = None, n_modes: Any = None) -> None:
    system = contract(lambda: duhamel.System(*system_args, **(kwargs or {})), ("M", "K"))
    assert system is not None
    basis = contract(lambda: system.modal(n_modes), ("modes", "n_modes"))
    if basis is not None:
        for name in ("phi", "omega2", "omega", "c", "zeta"):
            value = getattr(basis, name)
            assert np.all(np.isfinite(value)), f"ModalBasis.{name} = {value!r}"


def _with_law(system: duhamel.System) -> duhamel.System:
    return system.set_mass_law(MS.Exponential(-0.1))


def _rotor_case_d8(x_stat: float | None, rho: float = 7810.0) -> Any:
    R = _rotor()
    shaft = R.Shaft(1.0, 0.125, material=R.Material(E=211e9, rho=rho, nu=0.0))
    bearings = [R.Bearing(0, 1e7, 1e7), R.Bearing(1, 1e7, 1e7, beta=0.5, x_stat=x_stat)]
    disks = [R.Disk(0, 1.0, 1.0, 1.0)] if x_stat is not None else []
    rotor = R.Rotor([shaft], disks, bearings)
    return contract(lambda: rotor.system(0.0), ("x_stat", "beta"))


def _rotor_case_d9(kyy: float | None = None) -> Any:
    R = _rotor()
    material = R.Material(E=211e9, rho=7810.0, nu=0.0)
    if kyy is None:  # a needle of a shaft on a stiff bearing
        shaft = R.Shaft(1.0, 1e-150, material=material)
        first = R.Bearing(0, kxx=1e150, kyy=1e7, cxx=1e3, cyy=1e3)
        second = R.Bearing(1, 1e7, 1e7, cxx=1e3, cyy=1e3)
    else:  # an ordinary shaft on a bearing of the largest finite stiffness
        shaft = R.Shaft(1.0, 0.125, material=material)
        first = R.Bearing(0, 1e7, 1e7, cxx=1e3, cyy=1e3)
        second = R.Bearing(1, kxx=1e7, kyy=kyy, cxx=1e3, cyy=1e3)
    rotor = R.Rotor([shaft], [], [first, second], zeta=0.0)
    return contract(lambda: rotor.system(0.0), ("outer_diameter", "kxx", "kyy"))


#: id -> (defect, the minimal case found by the property tests).
KNOWN_CASES: dict[str, tuple[str, Callable[[], Any]]] = {
    "D2-sparse-modal(1)-K=1e300": (
        "D2",
        lambda: _modal((sp.csr_array(np.eye(3)), 1e300 * CHAIN3), n_modes=1),
    ),
    "D3-modal-M=1e-300-K=0-C": (
        "D3",
        lambda: _modal((1e-300 * np.eye(2), np.zeros((2, 2)), 1e8 * CHAIN2)),
    ),
    "D3-modal-M=1e-300-K=1e8": ("D3", lambda: _modal((1e-300 * np.eye(3), 1e8 * CHAIN3))),
    "D3-CentralDifference-LinAlgError": (
        "D3",
        lambda: run(
            _with_law(duhamel.System(np.diag([1.0, 1e-150, 1.0]), 1e300 * CHAIN3)),
            duhamel.CentralDifference(),
            t_end=1e-9,
            dt=1e-9,
        ),
    ),
    "D4-modal-phi-NaN": ("D4", lambda: _modal((1e-300 * np.eye(2), 1e8 * CHAIN2))),
    "D4-modal-c-inf": ("D4", lambda: _modal(([[5e-151]], [[1e8]]), {"rayleigh": (0.0, 1e150)})),
    "D4-modal-c-inf-zeta": ("D4", lambda: _modal((np.eye(2), CHAIN2), {"zeta": 5.6e307})),
    "D5-v-inf": (
        "D5",
        lambda: run(
            duhamel.System([[1e-150]], [[1.0]]),
            duhamel.Semianalytic(),
            t_end=1e-9,
            dt=1e-9,
            x0=[1e300],
        ),
    ),
    "D5-x-inf": (
        "D5",
        lambda: run(
            duhamel.System(np.diag([1.0, 1.0, 1.0, 1e-300]), np.zeros((4, 4))).add_load(
                L.Callable(Sine(1e150, 4))
            ),
            duhamel.Semianalytic(),
            t_end=1e-9,
            dt=1e-9,
        ),
    ),
    "D6-finished-a-inf": (
        "D6",
        lambda: run(
            duhamel.System([[0.125]], [[1e300]]),
            duhamel.CubicHermite(),
            t_end=23e-9,
            dt=1e-9,
            v0=[1.0],
        ),
    ),
    "D6-partial-a-inf": (
        "D6",
        lambda: run(
            duhamel.System([[0.125]], [[1e300]]),
            duhamel.CubicHermite(),
            t_end=24e-9,
            dt=1e-9,
            v0=[1.0],
        ),
    ),
    "D7-t0=1e9-dt=1e-9": (
        "D7",
        lambda: run(_one(), duhamel.Semianalytic(), t0=1e9, t_end=1e9 + 1e-7, dt=1e-9, x0=[1.0]),
    ),
    "D7-t0=2**64-dt=1e3": (
        "D7",
        lambda: run(_one(), duhamel.Newmark(), t0=2.0**64, t_end=2.0**64 + 52e3, dt=1e3),
    ),
    "D8-x_stat=1e300": ("D8", lambda: _rotor_case_d8(1e300)),
    "D8-x_stat=1e-300": ("D8", lambda: _rotor_case_d8(1e-300)),
    "D8-static-deflection-rho=2.23e162": (
        "D8",
        lambda: _rotor_case_d8(None, rho=2.227454599256807e162),
    ),
    "D9-rotor-LinAlgError": ("D9", _rotor_case_d9),
    "D9-rotor-kyy=float_max": ("D9", lambda: _rotor_case_d9(kyy=sys.float_info.max)),
    "D12-CentralDifference-mass-law-to-0": (
        "D12",
        lambda: run(
            _one().set_mass_law(MS.Exponential(-0.1)),
            duhamel.CentralDifference(),
            t_end=8000.0,
            dt=1000.0,
        ),
    ),
    "D11-theta-overflow": (
        "D11",
        lambda: _speed_law_case(S.LinearRunUp(2e300, 0.0, 1.0), -1e8),
    ),
}


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize("case", list(KNOWN_CASES))
def test_former_defect(case):
    """The minimal cases of the defects this suite found (``DEFECTS``), fixed: regression
    tests."""
    KNOWN_CASES[case][1]()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(pytest.main([__file__, "-q"]))


# --------------------------------------------------------------------------------------------
# The modules beyond solve (issue 24): records, spectra, devices, ensembles, stores, rotors
# --------------------------------------------------------------------------------------------

import pathlib  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402

from duhamel.records import GroundMotion, read_at2, read_text  # noqa: E402
from duhamel.spectra import ductility_spectrum, response_spectrum, rotd  # noqa: E402

#: Files and stores the properties below write (one directory per process).
_SCRATCH = pathlib.Path(tempfile.mkdtemp(prefix="duhamel-properties-"))

#: Header DT fields: good (Fortran D and E exponents), and damaged.
_DT_TOKENS = ["0.005", ".0050", "5.0D-03", "5.0d-3", "5E-3", "0", "-0.01", "1D999", "nan", "",
              "x", "0.0.1", "+.5", "1e-320", "1e308"]  # fmt: skip
#: Data tokens: numbers of every form, and damaged ones.
_VALUE_TOKENS = ["0.1", "-.2E-02", ".3D+01", "1e308", "1e999", "-1e-320", "5", "nan", "inf",
                 "1,2", "--1", "1e", "abc", "\t", "1.0E+00-2.0E+00"]  # fmt: skip


def _file(name: str, text: str) -> pathlib.Path:
    p = _SCRATCH / name
    p.write_text(text, encoding="latin-1")
    return p


def check_motion(gm: Any) -> None:
    assert isinstance(gm, GroundMotion)
    assert gm.dt > 0 and math.isfinite(gm.dt) and np.all(np.isfinite(gm.a)), gm
    assert np.all(np.isfinite(gm.t)), gm
    for name in ("pga", "pgv", "pgd", "arias_intensity"):
        value = contract(lambda n=name: getattr(gm, n), (name, "overflows"))
        if value is not None:
            assert math.isfinite(value), (name, value)
    if np.any(gm.a):
        d = contract(gm.significant_duration, ("start", "end"))
        assert d is not None and math.isfinite(d) and d >= 0.0, d


@budget(1.0)
@given(
    dt=st.sampled_from(_DT_TOKENS),
    npts=st.integers(-1, 12),
    values=st.lists(st.sampled_from(_VALUE_TOKENS), max_size=12),
    style=st.sampled_from(["new", "old", "broken"]),
    units=st.sampled_from([None, "g", "G.", "furlongs", 3]),
    lines=st.integers(0, 6),
)
def test_at2_files_read_or_refused_by_line(dt, npts, values, style, units, lines):
    header = {
        "new": f"NPTS= {npts}, DT= {dt} SEC",
        "old": f"{npts} {dt} NPTS, DT",
        "broken": f"NPTS {npts} DT {dt}",
    }[style]
    kind = f"ACCELERATION TIME SERIES IN UNITS OF {units or 'G'}"
    text = "\n".join(["TITLE", "EVENT", kind, header, " ".join(values)][: max(lines, 0) or 5])
    p = _file("prop.AT2", text)
    gm = contract(lambda: read_at2(p, units=units if units != "G." else None), (str(p), "units"))
    if gm is not None:
        check_motion(gm)
        assert gm.a.size == npts, (gm.a.size, npts)


@budget(1.0)
@given(
    rows=st.lists(st.lists(st.sampled_from(_VALUE_TOKENS[:7]), min_size=1, max_size=3),
                  max_size=6),
    dt=st.one_of(st.none(), scalar(EXTREME.positives)),
    time_column=st.one_of(st.none(), st.sampled_from([0, 1, -1, 1.5, True, 10**400])),
    column=st.one_of(st.none(), st.sampled_from([0, 1, 2, -2, 0.5, "1"])),
    skip_rows=st.sampled_from([0, 1, -3, 2.0, None, 10**30]),
    flatten=st.sampled_from([False, True, "no", 0, None]),
)  # fmt: skip
def test_text_records_read_or_refused(rows, dt, time_column, column, skip_rows, flatten):
    p = _file("prop.txt", "\n".join(" ".join(r) for r in rows))
    gm = contract(
        lambda: read_text(p, units="m/s^2", dt=dt, time_column=time_column, column=column,
                          skip_rows=skip_rows, flatten=flatten),
        (str(p),),
    )  # fmt: skip
    if gm is not None:
        check_motion(gm)


def _records(dom: Domain) -> st.SearchStrategy:
    return st.builds(
        lambda scale, a, dt: (dt * np.arange(a.size), scale * a),
        dom.scales,
        hnp.arrays(np.float64, st.integers(2, 40), elements=floats(-10.0, 10.0)),
        st.sampled_from([1e-3, 0.005, 0.02, 0.1, 1.0]),
    )


def _spectrum_periods(dom: Domain) -> st.SearchStrategy:
    return st.one_of(
        st.lists(st.one_of(st.just(0.0), dom.positives, st.sampled_from([1e-300, 1e-100, 1e300])),
                 min_size=1, max_size=3),
        nasty_scalars,
    )  # fmt: skip


_THREADS = st.sampled_from([None, 1, 2, 0, -1, True, 1.5, 10**6, 2**64, "2"])


@budget(1.0)
@given(
    rec=_records(EXTREME),
    periods=_spectrum_periods(EXTREME),
    damping=st.one_of(st.sampled_from([0.0, 0.05, 2.0, -0.1, [0.02, 0.1]]), nasty_scalars),
    threads=_THREADS,
)
def test_response_spectra_finite_or_refused(rec, periods, damping, threads):
    rs = contract(lambda: response_spectrum(rec, periods, damping, threads=threads),
                  ("motions", "periods", "damping", "threads"))  # fmt: skip
    if rs is not None:
        for name in ("sd", "sv", "sa", "psv", "psa"):
            value = getattr(rs, name)
            assert np.all(np.isfinite(value)), (name, value)


@budget(0.7)
@given(
    rec=_records(EXTREME),
    periods=_spectrum_periods(ORDINARY),
    n_angles=st.sampled_from([1, 2, 180, 0, -1, 1.5, 10**9, 10**5, True]),
    percentiles=st.sampled_from([(50, 100), (0,), (101,), (-1, 50), "50"]),
    threads=_THREADS,
)
def test_rotd_finite_or_refused(rec, periods, n_angles, percentiles, threads):
    other = (rec[0], rec[1][::-1].copy())
    names = ("motion_1", "motion_2", "periods", "percentiles", "n_angles", "threads")
    r = contract(
        lambda: rotd(rec, other, periods, percentiles, n_angles=n_angles, threads=threads), names
    )
    if r is not None:
        assert np.all(np.isfinite(r.sd)) and np.all(np.isfinite(r.psa)), r.sd


@budget(0.7)
@given(
    rec=_records(EXTREME),
    periods=st.lists(st.one_of(ORDINARY.positives, st.sampled_from([1e-20, 1e-14, 1e3])),
                     min_size=1, max_size=2),
    ductility=st.sampled_from([[1.0], [2.0], [1.0, 4.0], [0.5], [1e6]]),
    alpha=st.sampled_from([0.0, 0.1, 0.99, 1.0, -0.1, "0"]),
    zero=st.booleans(),
)  # fmt: skip
def test_ductility_spectra_finite_or_refused(rec, periods, ductility, alpha, zero):
    t, a = rec
    ds = contract(
        lambda: ductility_spectrum((t, 0.0 * a if zero else a), periods, ductility, alpha=alpha),
        ("motions", "periods", "ductility", "alpha"),
    )
    if ds is not None:
        for name in ("uy", "fy", "sd", "r"):
            value = getattr(ds, name)
            assert np.all(np.isfinite(value)) and np.all(value > 0), (name, value)


@st.composite
def devices(draw: Any, dom: Domain) -> Any:
    """A device at extreme parameters (made under the contract: None if refused)."""
    kind = draw(st.sampled_from(["boucwen", "friction", "viscous", "gap", "bilinear"]))
    mag, pos = scalar(dom.magnitudes), scalar(dom.positives)
    if kind == "boucwen":
        n = draw(st.one_of(st.sampled_from([1.0, 1.5, 2.0, 17.0, 1e3, 1e6, 1e12, 0.5]), mag))
        return construct(Call(("k", "fy", "alpha", "n", "beta", "gamma"), E.BoucWen, 0,
                              k=draw(pos), fy=draw(pos), alpha=draw(st.sampled_from([0.0, 0.1])),
                              n=n, beta=draw(st.sampled_from([0.5, 0.25, 0.9])),
                              gamma=draw(st.sampled_from([0.5, 0.75, -0.2]))))  # fmt: skip
    if kind == "friction":
        return construct(Call(("radius", "mu", "weight", "yield_displacement"),
                              E.FrictionPendulum, 0, 1, radius=draw(pos), mu=draw(mag),
                              weight=draw(pos), yield_displacement=draw(pos)))  # fmt: skip
    if kind == "viscous":
        return construct(Call(("c", "exponent", "v0"), E.ViscousDamper, 0, c=draw(mag),
                              exponent=draw(pos), v0=draw(pos)))  # fmt: skip
    if kind == "gap":
        return construct(Call(("gap", "k"), E.Gap, 0, gap=draw(mag), k=draw(pos)))
    return construct(Call(("k", "fy", "alpha"), E.Bilinear, 0, k=draw(pos), fy=draw(pos),
                          alpha=draw(st.sampled_from([0.0, 0.05]))))  # fmt: skip


@budget(1.0)
@given(device=devices(EXTREME), amplitude=EXTREME.magnitudes, dt=st.sampled_from([1e-3, 0.05]))
def test_devices_at_extreme_parameters_run_or_refuse(device, amplitude, dt):
    assume(device is not None)
    s = duhamel.System(np.eye(2), np.diag([1.0, 2.0]), zeta=0.05)
    s.add(device)
    s.add_load(L.Harmonic(0, amplitude=amplitude, omega=1.0))
    run(s, duhamel.Semianalytic(), t_end=40 * dt, dt=dt)


# -- ensembles with failing and odd make_system / reduce --------------------------------------


def _odd_system(kind: str) -> Callable[[Any], Any]:
    def make(p: Any) -> Any:
        s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
        s.add_load(L.Harmonic(0, amplitude=1.0, omega=1.0))
        if kind == "raises":
            raise UserError("make_system failed")
        if kind == "none":
            return None
        if kind == "options" and p > 1:
            return s, {"x0": [float(p)]}
        if kind == "bad-options":
            return s, {"t_end": 3.0}
        if kind == "diverges" and p > 1:
            s.add(E.Cubic(0, k3=-1e6))
            return s, {"x0": [10.0]}
        return s

    return make


def _odd_reduce(kind: str) -> Any:
    return {
        "none": None,
        "peak": lambda sol: float(np.abs(sol.x).max()),
        "keys": lambda sol: {"a": 1.0} if sol.x[0, 0] > 1 else {"a": 1.0, "b": 2.0},
        "nan": lambda sol: float("nan"),
        "raises": lambda sol: (_ for _ in ()).throw(UserError("reduce failed")),
        "junk": 3,
    }[kind]


@budget(0.6)
@given(
    system=st.sampled_from(["plain", "raises", "none", "options", "bad-options", "diverges"]),
    reduce=st.sampled_from(["none", "peak", "keys", "nan", "raises", "junk"]),
    params=st.sampled_from([[], [1.0], [1.0, 2.0], [0.5, 2.0, 3.0]]),
    workers=st.sampled_from([None, 1, 2, 0, 1.5, True]),
    on_error=st.sampled_from(["raise", "keep", "ignore"]),
    basis=st.sampled_from([None, "first", "all"]),
)
def test_solve_many_with_odd_callables(system, reduce, params, workers, on_error, basis):
    from duhamel.ensemble import solve_many

    def call() -> Any:
        try:
            return solve_many(_odd_system(system), params, duhamel.Semianalytic(), t_end=1.0,
                              dt=0.1, reduce=_odd_reduce(reduce), workers=workers,
                              on_error=on_error, basis=basis)  # fmt: skip
        except UserError as exc:  # documented: the failing run's own exception, with a note
            assert system == "raises" or reduce == "raises", exc
            return None

    ens = contract(call, ("make_system", "reduce", "workers", "on_error", "basis", "threads"))
    if ens is None:
        return
    assert len(ens.results) == len(params)
    pytest.importorskip("xarray")
    ds = contract(ens.to_xarray, ("reduce", "results", "cases"))
    if ds is not None:
        assert ds.sizes.get("case", 0) == len(params)


@budget(0.4)
@given(
    measures=hnp.arrays(np.float64, st.tuples(st.integers(1, 6), st.integers(1, 3)),
                        elements=st.one_of(floats(0.0, 10.0), st.just(np.inf))),
    q=st.lists(floats(0.0, 100.0), min_size=1, max_size=4),
)  # fmt: skip
def test_ida_fractiles_with_collapses(measures, q):
    from duhamel.ensemble import fractiles

    f = fractiles(measures, q)
    assert not np.isnan(f).any(), f
    finite = np.all(np.isfinite(measures), axis=0)
    np.testing.assert_array_equal(f[:, finite], np.percentile(measures[:, finite], q, axis=0))
    # monotone in q, and inf exactly above the last finite order statistic
    order = np.argsort(q)
    assert np.all(f[order][1:] >= f[order][:-1])
    n = measures.shape[0]
    k = np.sum(np.isinf(measures), axis=0)
    for j in range(measures.shape[1]):
        if 0 < k[j] < n:
            for qi, value in zip(q, f[:, j], strict=True):
                h = (n - 1) * (qi / 100.0)  # the position among the order statistics
                assert np.isinf(value) == (h > n - k[j] - 1), (qi, value, h)


# -- the streaming store under damage ----------------------------------------------------------

_STORE: dict[str, Any] = {}


def _pristine() -> tuple[pathlib.Path, np.ndarray]:
    """One small complete store (3 segments of 1024 rows), made once per process."""
    if not _STORE:
        pytest.importorskip("zarr")
        from duhamel.store import Store

        path = _SCRATCH / "pristine.zarr"
        s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], zeta=0.02)
        s.add(E.Bilinear(0, k=0.5, fy=0.05))
        s.add_load(L.Harmonic(1, amplitude=0.3, omega=0.9))
        sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=30.0, dt=0.01,
                            store=Store(path, segment_bytes=1))  # fmt: skip
        _STORE.update(path=path, x=np.asarray(sol.x), files=sorted(
            str(f.relative_to(path)) for f in path.rglob("*") if f.is_file()))  # fmt: skip
    return _STORE["path"], _STORE["x"]


@budget(0.8)
@given(data=st.data(), damage=st.sampled_from(["delete", "truncate", "flip", "garbage", "grid"]))
def test_store_damage_is_detected_or_harmless(data, damage):
    from duhamel.store import StoreError, resume

    pristine, x = _pristine()
    path = _SCRATCH / "damaged.zarr"
    shutil.rmtree(path, ignore_errors=True)
    shutil.copytree(pristine, path)
    name = data.draw(st.sampled_from(_STORE["files"]), label="file")
    target = path / name
    raw = target.read_bytes()
    if damage == "delete":
        target.unlink()
    elif damage == "truncate":
        target.write_bytes(raw[: data.draw(st.integers(0, max(0, len(raw) - 1)))])
    elif damage == "flip" and raw:
        i = data.draw(st.integers(0, len(raw) - 1), label="byte")
        bit = data.draw(st.integers(0, 7), label="bit")
        target.write_bytes(raw[:i] + bytes([raw[i] ^ (1 << bit)]) + raw[i + 1 :])
    elif damage == "garbage":
        target.write_bytes(data.draw(st.binary(max_size=64), label="garbage"))
    else:
        import json

        import zarr

        group = zarr.open_group(path)
        record = dict(group.attrs["duhamel"])
        key = data.draw(st.sampled_from(["n_steps", "rows", "save_every", "dt", "dofs"]))
        value = data.draw(st.sampled_from([10**18, -1, 0, 1.5, "7", None, [99], 2**64]))
        record["grid"] = {**record["grid"], key: value}
        if data.draw(st.booleans(), label="checksum forged"):
            from duhamel.store._integrity import digest

            record["checksum"] = digest(
                record["grid"], record["model"], group["model"], record.get("store")
            )
        group.attrs["duhamel"] = json.loads(json.dumps(record))

    def call() -> Any:
        try:
            return resume(path)
        except FileNotFoundError as exc:  # the store's root deleted: documented
            check_named(exc, ("path",))
            return None
        except StoreError as exc:
            assert "damaged" in str(exc) or "not a" in str(exc) or "format" in str(exc), exc
            assert str(path) in str(exc) or "`path`" in str(exc), exc
            return None

    sol = contract(call, ("path",))
    if sol is not None:  # a harmless damage (a slot, rows beyond the checkpoint): same data
        np.testing.assert_array_equal(np.asarray(sol.x), x)


# -- rotor grids and journal geometries ---------------------------------------------------------

_ROTOR: dict[str, Any] = {}


def _small_rotor() -> Any:
    if not _ROTOR:
        from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft

        _ROTOR["rotor"] = Rotor(
            [Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
            [Bearing(0, 1e7, 1e7, cxx=500.0, cyy=500.0),
             Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)],
        )  # fmt: skip
        _ROTOR["fine"] = _ROTOR["rotor"].critical_speeds(np.linspace(0.0, 3000.0, 121))
    return _ROTOR["rotor"]


@budget(0.4)
@given(
    grid=st.lists(st.one_of(floats(0.0, 3000.0), st.sampled_from([0.0, 1e6, 1e20, 1e300])),
                  min_size=1, max_size=5),
    whirl=st.sampled_from(["forward", "backward", None, "both"]),
    harmonic=st.sampled_from([1.0, 2.0, 0.5, 0.0, -1.0, "1"]),
)  # fmt: skip
def test_critical_speeds_on_any_grid(grid, whirl, harmonic):
    rotor = _small_rotor()
    found = contract(lambda: rotor.critical_speeds(grid, whirl=whirl, harmonic=harmonic),
                     ("speeds", "whirl", "harmonic"))  # fmt: skip
    if found is not None:
        found = np.asarray(found)  # a CriticalSpeeds: as an array, its speeds
        assert np.all(np.isfinite(found)) and np.all(found >= 0), found
        h = float(harmonic)
        for w in found[(found > 0) & (found < 1e6)]:
            gap = np.min(np.abs(rotor.modes(float(w)).frequencies - h * w))
            assert gap <= 1e-6 * h * w, (w, gap)


@budget(0.6)
@given(
    geometry=st.tuples(*(scalar(EXTREME.positives) for _ in range(4))),
    position=st.tuples(floats(-1.5, 1.5), floats(-1.5, 1.5)),
    speed=scalar(EXTREME.magnitudes),
)
def test_journal_coefficients_finite_or_refused(geometry, position, speed):
    from duhamel.rotor import ShortJournalBearing

    b = construct(Call(("diameter", "length", "clearance", "viscosity"), ShortJournalBearing,
                       0, *geometry))  # fmt: skip
    if b is None:
        return
    at = [position[0] * b.clearance, position[1] * b.clearance]
    out = contract(lambda: b.coefficients(at, speed), ("position", "speed", "clearance"))
    if out is not None:
        assert all(np.all(np.isfinite(m)) for m in out), out


def _damaged_slot_metadata() -> None:
    from duhamel.store import resume

    pristine, x = _pristine()
    path = _SCRATCH / "d13.zarr"
    shutil.rmtree(path, ignore_errors=True)
    shutil.copytree(pristine, path)
    (path / "checkpoints" / "1" / "zarr.json").write_bytes(b"\x80")
    np.testing.assert_array_equal(np.asarray(resume(path).x), x)


def _critical_case(grid: list[float], harmonic: float) -> None:
    rotor = _small_rotor()
    found = contract(lambda: rotor.critical_speeds(grid, harmonic=harmonic), ("speeds",))
    for w in [] if found is None else found:
        assert np.min(np.abs(rotor.modes(float(w)).frequencies - harmonic * w)) <= 1e-6 * w


ROUND2_CASES = {
    "D13-checkpoint-slot-metadata": ("D13", _damaged_slot_metadata),
    "D14-critical-speeds-1e300": ("D14", lambda: _critical_case([0.0, 1e300], 1.0)),
    "D15-critical-speeds-jump": ("D15", lambda: _critical_case([0.0, 1e6], 2.0)),
}


@pytest.mark.parametrize("case", list(ROUND2_CASES))
def test_former_defect_of_the_modules(case):
    """The minimal cases of the defects the module properties found, fixed."""
    assert ROUND2_CASES[case][0] in DEFECTS
    ROUND2_CASES[case][1]()
