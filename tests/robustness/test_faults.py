"""Inputs that used to abort or hang the interpreter end with a clear Python exception.

* A step count whose history cannot fit in memory is refused before anything is allocated,
  on every route, with what it needs and what to change (it used to abort the process with
  "memory allocation of 80000000008 bytes failed").
* An absurd ``threads`` is refused (it used to spawn threads until the OS refused: minutes).

The same cases also run in a subprocess with an address-space limit and a timeout: they must
end with a Python exception, never a crash or a hang.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest
from _callbacks import callback_failure

import duhamel
from duhamel import elements as E

GYRO = np.array([[0.0, 1.0], [-1.0, 0.0]])

ROUTES = {
    "uncoupled": (lambda: duhamel.System(np.eye(2), np.eye(2)), duhamel.Semianalytic()),
    "first-order": (
        lambda: duhamel.System(np.eye(2), np.eye(2)).add(E.LinearCoupling(C=GYRO)),
        duhamel.Semianalytic(),
    ),
    "pseudo-force": (
        lambda: duhamel.System(np.eye(2), np.eye(2)).add(E.Cubic(0, k3=1.0)),
        duhamel.Semianalytic(),
    ),
    "direct": (lambda: duhamel.System(np.eye(2), np.eye(2)), duhamel.Newmark()),
}


@pytest.mark.parametrize("route", list(ROUTES))
def test_a_history_too_large_for_memory_is_refused_before_the_run(route):
    make, integrator = ROUTES[route]
    with pytest.raises(ValueError, match=r"`save_every` is too small.*GiB.*memory") as info:
        duhamel.solve(make(), integrator, t_end=1e4, dt=1e-6)
    assert "larger `save_every`" in str(info.value)
    # Saving fewer steps makes the same run acceptable.
    sol = duhamel.solve(make(), integrator, t_end=1e-3, dt=1e-6, save_every=100)
    assert sol.t.size == 11


@pytest.mark.parametrize("route", ["uncoupled", "first-order"])
def test_absurd_thread_counts_are_refused(route):
    make, integrator = ROUTES[route]
    with pytest.raises(ValueError, match=r"`threads` must be between 1 and 1024, got 1000000"):
        duhamel.solve(make(), integrator, t_end=1.0, dt=0.1, threads=10**6)
    # More threads than cores is allowed (and uses the cores there are).
    sol = duhamel.solve(make(), integrator, t_end=1.0, dt=0.1, threads=64, x0=[1.0, 0.0])
    one = duhamel.solve(make(), integrator, t_end=1.0, dt=0.1, threads=1, x0=[1.0, 0.0])
    np.testing.assert_array_equal(sol.x, one.x)


ISOLATED = textwrap.dedent(
    """
    import json, resource, sys
    import numpy as np
    import duhamel
    from duhamel import elements as E

    # 4 GiB of address space: an allocation of the whole history would fail here.
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    gyro = np.array([[0.0, 1.0], [-1.0, 0.0]])
    cases = {
        "uncoupled": (duhamel.System(np.eye(2), np.eye(2)), duhamel.Semianalytic(), {}),
        "first-order": (
            duhamel.System(np.eye(2), np.eye(2)).add(E.LinearCoupling(C=gyro)),
            duhamel.Semianalytic(),
            {},
        ),
        "pseudo-force": (
            duhamel.System(np.eye(2), np.eye(2)).add(E.Cubic(0, 1.0)),
            duhamel.Semianalytic(),
            {},
        ),
        "direct": (duhamel.System(np.eye(2), np.eye(2)), duhamel.Newmark(), {}),
        "threads": (duhamel.System(np.eye(2), np.eye(2)), duhamel.Semianalytic(),
                    {"threads": 10**6, "t_end": 1.0, "dt": 0.1}),
    }
    out = {}
    for name, (system, integrator, kw) in cases.items():
        run = {"t_end": 1e4, "dt": 1e-6} | kw
        try:
            duhamel.solve(system, integrator, **run)
            out[name] = "returned"
        except Exception as exc:
            out[name] = type(exc).__name__
    print(json.dumps(out))
    """
)


def test_former_crashes_end_with_an_exception_in_a_limited_subprocess():
    proc = subprocess.run(
        [sys.executable, "-c", ISOLATED], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out == {name: "ValueError" for name in [*ROUTES, "threads"]}, out


# --------------------------------------------------------------------------------------------
# Clear messages instead of leaked OverflowError, IndexError, truncation or silence
# --------------------------------------------------------------------------------------------


def _one() -> duhamel.System:
    return duhamel.System(np.eye(1), np.eye(1))


@pytest.mark.parametrize(
    ("run", "pattern"),
    [
        ({"t_end": 1.0, "dt": 5e-324}, r"`dt` = .* is too small .* inf steps"),
        ({"t_end": 1e300, "dt": 1.0}, r"`dt` = 1 is too small .* 1e\+300 steps"),
    ],
    ids=["tiny dt", "huge t_end"],
)
def test_step_counts_beyond_counting_are_refused(run, pattern):
    with pytest.raises(ValueError, match=pattern):
        duhamel.solve(_one(), duhamel.Semianalytic(), **run)


def test_a_save_stride_beyond_the_run_keeps_its_ends():
    sol = duhamel.solve(
        _one(), duhamel.Semianalytic(), t_end=1.0, dt=0.1, save_every=2**64, x0=[1.0]
    )
    assert sol.t.tolist() == [0.0, 1.0]
    with pytest.raises(ValueError, match=r"`save_every` must be at most"):
        duhamel.solve(_one(), duhamel.Semianalytic(), t_end=1.0, dt=0.1, save_every=2**65)


@pytest.mark.parametrize(
    "make",
    [
        lambda: duhamel.Semianalytic(max_iter=10**30),
        lambda: duhamel.Newmark(max_iter=10**30),
        lambda: duhamel.CubicHermite(max_iter=10**30),
    ],
    ids=["Semianalytic", "Newmark", "CubicHermite"],
)
def test_absurd_iteration_counts_are_refused(make):
    with pytest.raises(ValueError, match=r"`max_iter` must be at most 10,000"):
        make()


def test_numpy_scalars_are_numbers():
    integrator = duhamel.Semianalytic(modes=np.int64(1), tol=np.float32(1e-6))
    assert integrator.modes == 1
    newmark = duhamel.Newmark(gamma=np.float64(0.5), max_iter=np.int64(5))
    for chosen in (integrator, newmark):
        sol = duhamel.solve(
            _one(), chosen, t_end=1.0, dt=np.float32(0.5), save_every=np.int64(1), x0=[1.0]
        )
        assert sol.t.size == 3 and np.all(np.isfinite(sol.x))


@pytest.mark.parametrize(
    ("jacobian", "got"),
    [
        (lambda x, v, t: None, "a NoneType"),
        (lambda x, v, t: np.eye(1), "a ndarray"),
        (lambda x, v, t: (np.eye(1), np.eye(1), np.eye(1)), "a tuple of 3 items"),
    ],
    ids=["None", "one matrix", "three matrices"],
)
def test_a_wrong_jacobian_is_named(jacobian, got):
    element = E.Callable([0], lambda x, v, t: x**3, jacobian=jacobian)
    with callback_failure(ValueError, rf"jacobian returned {got}, expected a pair"):
        duhamel.solve(_one().add(element), duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0])


def test_complex_element_values_are_refused_not_truncated():
    element = E.Callable([0], lambda x, v, t: x**3 + 1j)
    with callback_failure(ValueError, r"dtype complex128, expected real numbers"):
        duhamel.solve(_one().add(element), duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0])


def test_hold_must_be_a_bool():
    with pytest.raises(TypeError, match=r"`hold` must be True or False, got 'no'"):
        duhamel.loads.Tabulated(0, t=[0.0, 1.0], values=[0.0, 1.0], hold="no")


def test_a_damping_ratio_above_one_warns():
    with pytest.warns(duhamel.DampingWarning, match=r"`zeta` = 5 is above 1.*pass 0.05"):
        duhamel.System(np.eye(1), np.eye(1), zeta=5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
        duhamel.System(np.eye(1), np.eye(1), zeta=1.0)


@pytest.mark.parametrize("length", [1e300, 1e-300])
def test_shafts_whose_matrices_overflow_are_refused(length):
    from duhamel import rotor as R

    steel = R.Material(E=211e9, rho=7810.0, nu=0.3)
    with pytest.raises(ValueError, match=r"`L` = .* gives non-finite element matrices"):
        R.Shaft(length, 0.05, material=steel)


# --------------------------------------------------------------------------------------------
# Wrong physics refused: indefinite stiffness behind an ill-conditioned mass, vanishing mass
# --------------------------------------------------------------------------------------------


def test_indefinite_stiffness_is_refused_whatever_the_mass_conditioning():
    # Its generalised eigenvalue -3 used to be clamped to a rigid-body mode (the negativity
    # test was relative to the largest eigenvalue, 1e10 here): x = 0.001 where the response
    # grows.
    system = duhamel.System(np.diag([1.0, 1e-10]), [[1.0, 2.0], [2.0, 1.0]])
    with pytest.raises(ValueError, match=r"`K` must be positive semidefinite.*-1 < 0"):
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0, 0.0])
    # A true rigid-body mode behind the same mass stays one.
    free = duhamel.System(np.diag([1.0, 1e-10]), [[1.0, -1.0], [-1.0, 1.0]])
    assert free.modal().omega2[0] == 0.0


@pytest.mark.parametrize("n_modes", [None, 3], ids=["all modes", "shift-invert Lanczos"])
def test_indefinite_sparse_stiffness_is_refused(n_modes):
    import scipy.sparse as sp

    # The same trap in a sparse chain: a positive diagonal, a 2x2 block [[1, 2], [2, 1]]
    # (eigenvalue -1) and a tiny mass where it sits.
    n = 40
    k = sp.lil_array(sp.diags([np.full(n, 2.0), -np.ones(n - 1), -np.ones(n - 1)], [0, 1, -1]))
    k[0, 0], k[1, 1], k[0, 1], k[1, 0], k[1, 2], k[2, 1] = 1.0, 1.0, 2.0, 2.0, 0.0, 0.0
    m = sp.diags(np.r_[1.0, 1e-10, np.ones(n - 2)])
    system = duhamel.System(m.tocsr(), k.tocsr())
    with pytest.raises(ValueError, match=r"`K` must be positive semidefinite"):
        system.modal(n_modes)
    # the free-free chain (a true rigid-body mode) behind the same mass is accepted
    free = sp.lil_array(sp.diags([np.full(n, 2.0), -np.ones(n - 1), -np.ones(n - 1)], [0, 1, -1]))
    free[0, 0] = free[n - 1, n - 1] = 1.0
    assert duhamel.System(m.tocsr(), free.tocsr()).modal(n_modes).omega2[0] == 0.0


def test_mass_laws_must_stay_above_their_floor():
    with pytest.raises(ValueError, match=r"`mu` must stay above 1e-08 of its largest value"):
        duhamel.mass.Tabulated(t=[0.0, 1.0], mu=[1.0, 1e-300])
    decaying = duhamel.System(np.eye(1), np.eye(1))
    decaying.set_mass_law(duhamel.mass.Exponential(rate=-1.0))
    with pytest.raises(ValueError, match=r"`mass law` falls to .* of its largest value"):
        duhamel.solve(decaying, duhamel.Semianalytic(), t_end=100.0, dt=0.1, x0=[1.0])
    # Over a span it can take, the same law runs.
    sol = duhamel.solve(decaying, duhamel.Semianalytic(), t_end=10.0, dt=0.1, x0=[1.0])
    assert np.all(np.isfinite(sol.x))


def test_step_matrices_are_finite_or_refused():
    # These returned inf or NaN without a word. The first truly overflows (growth e^(2e4)):
    # refused. The other three have ordinary true values, now evaluated (checked against a
    # high-precision reference in test_oscillator.py::test_extreme_parameters_...).
    from duhamel.oscillator import transfer_matrices

    with pytest.raises(ValueError, match=r"cannot be evaluated in double precision"):
        transfer_matrices(1.0, -1000.0, 10.0)
    a, b = transfer_matrices(1e200, 0.05, 1.0)  # decays within the step; x = p / 1e400
    assert np.all(a == 0.0) and np.all(b == 0.0)
    a, b = transfer_matrices(1.0, 0.1, 1e300)  # decays; the end load's static response
    assert np.all(a == 0.0) and b[0, 0] == 1.0 and b[0, 1] == 1.0
    a, b = transfer_matrices(1.0, 1e300, 1.0)  # the state creeps: x stays, v dies
    assert a[0, 0] == 1.0 and a[0, 1] == pytest.approx(5e-301, rel=1e-15)


# --------------------------------------------------------------------------------------------
# No NaN or inf without an error; finite partial histories
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("integrator", ["Semianalytic", "Newmark"])
def test_a_tiny_mass_gives_finite_accelerations(integrator):
    # Finite x but NaN/inf accelerations with only a RuntimeWarning: the modal acceleration
    # folded omega^2 = 1e300 into mode shapes of size 1e150. The true a = f/m = 1e300.
    system = duhamel.System(1e-300 * np.eye(2), np.eye(2)).add_load(
        duhamel.loads.Step(0, amplitude=1.0)
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = duhamel.solve(system, getattr(duhamel, integrator)(), t_end=1e-149, dt=1e-152)
        a = sol.a
    assert np.all(np.isfinite(sol.x)) and np.all(np.isfinite(a))
    # x = (1 - cos w t) / k with w = 1e150: a = cos(w t) / m (exact for the semi-analytic
    # method; Newmark's period error over 1000 steps of w dt = 0.01 is about 1e-3)
    w, t = 1e150, sol.t
    tol = 1e-9 if integrator == "Semianalytic" else 1e-2
    assert np.allclose(a[:, 0], np.cos(w * t) * 1e300, rtol=0, atol=tol * 1e300)


def test_accelerations_beyond_the_double_range_raise():
    # x stays finite (1e-8), omega^2 x = 1e300 * 1e10 does not: reading `a` says so.
    system = duhamel.System(np.eye(1), [[1e300]])
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=1e-150, dt=1e-151, x0=[1e10])
    assert np.all(np.isfinite(sol.x))
    with pytest.raises(FloatingPointError, match=r"accelerations .* overflow at t = 0\.0"):
        _ = sol.a


def test_a_run_that_keeps_nothing_says_so():
    # The initial acceleration overflows (K x0 = 1e300 * 1e10): nothing can be kept, and the
    # message must not claim a history up to t = 0.
    system = duhamel.System(np.eye(1), [[1e300]])
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(system, duhamel.Newmark(), t_end=1.0, dt=0.1, x0=[1e10])
    err = info.value
    assert err.reason == "nonfinite" and err.partial.t.size == 0
    assert "nothing is kept" in str(err) and "history up to" not in str(err)
