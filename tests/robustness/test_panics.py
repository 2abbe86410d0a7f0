"""A panic in the native core is a bug, and comes out as ``duhamel.errors.InternalError``.

Never an abort of the interpreter, never pyo3's ``PanicException`` (a ``BaseException`` that
``except Exception`` misses): the binding catches the unwind at every entry point that runs
engine code (``crates/duhamel-py/src/guard.rs``), also when the panic happened in a rayon
worker or a scoped thread. ``_core._panic_for_tests`` panics on purpose (test only).

The second half holds the regression tests of the audit for panics reachable from input:
each input here used to panic (or wrap an integer, or be misread) and is now refused with a
``ValueError`` naming the parameter, or answered.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import duhamel
from duhamel import _core
from duhamel.errors import DuhamelError, InternalError

ROOT = Path(__file__).resolve().parents[2]
KINDS = {
    "here": "forced panic (test)",
    "detached": "forced panic with the GIL released (test)",
    "rayon": "forced panic in a rayon worker (test, item 37)",
    "thread": "forced panic in a scoped thread (test)",
}


# --- a panic becomes InternalError ---------------------------------------------------------


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_panic_raises_internal_error(kind):
    with pytest.raises(InternalError) as info:
        _core._panic_for_tests(kind)
    err = info.value
    assert isinstance(err, DuhamelError) and isinstance(err, RuntimeError)
    message = str(err)
    # The panic's own message (for a scoped thread, the worker's, not only the scope's),
    # where it happened, and what to do.
    assert KINDS[kind] in message
    assert "guard.rs:" in message
    assert "bug in duhamel" in message and "report it" in message


def test_except_exception_catches_it_and_the_library_still_works():
    try:
        _core._panic_for_tests("rayon")
    except Exception as err:  # not a BaseException only, as pyo3's PanicException is
        caught = err
    assert type(caught) is InternalError
    sys_ = duhamel.System(np.eye(2), np.diag([1.0, 4.0]), zeta=0.02)
    sys_.add_load(duhamel.loads.Step(dof=0, amplitude=1.0))
    sol = duhamel.solve(sys_, duhamel.Semianalytic(), t_end=1.0, dt=0.01, threads=2)
    assert np.isfinite(sol.x).all() and sol.x.shape == (101, 2)


def test_the_test_hook_checks_its_argument():
    with pytest.raises(ValueError, match="`kind`"):
        _core._panic_for_tests("nowhere")


def test_internal_error_is_exported():
    assert duhamel.InternalError is InternalError
    assert "InternalError" in duhamel.__all__
    assert issubclass(InternalError, duhamel.DuhamelError)


def test_a_caught_panic_prints_nothing_without_rust_backtrace():
    env = {k: v for k, v in os.environ.items() if k != "RUST_BACKTRACE"}
    code = (
        "import duhamel\n"
        "from duhamel import _core\n"
        "try:\n"
        "    _core._panic_for_tests('rayon')\n"
        "except duhamel.InternalError:\n"
        "    print('caught')\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=60
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "caught"
    assert "panicked" not in out.stderr


def test_release_profile_unwinds():
    """With `panic = "abort"` no panic could be caught: the process would die."""
    cargo = tomllib.loads((ROOT / "Cargo.toml").read_text())
    for profile in cargo.get("profile", {}).values():
        assert profile.get("panic", "unwind") == "unwind"


# --- inputs that used to panic ------------------------------------------------------------


def f64(*values):
    return np.array(values, dtype=np.float64)


def grid(**changes):
    return _core.Grid(**({"t0": 0.0, "dt": 0.1, "n_steps": 10, "save_every": 1} | changes))


def modal_model(n=1, route=None, phi=None):
    """Uncoupled unit oscillators (`route` None) with no loads."""
    phi = np.eye(n) if phi is None else phi
    return _core.ModalModel(np.ones(n), np.zeros(n), phi, [], route)


def modal_run(n=1, eta0=None, **changes):
    return _core.RunSpec(grid(**changes), np.zeros(n), np.zeros(n), eta0)


def first_order_route(r=2, m=1, corrector=None):
    return _core.FirstOrderRoute(
        -np.ones(r), np.ones(r), np.ones((r, m)), np.zeros((r, m)), corrector
    )


def direct_model(n=1):
    matrices = _core.Matrices(_core.Matrix.dense(np.eye(n)), _core.Matrix.dense(np.eye(n)))
    method = _core.Method.alpha(0.0, 0.0, 0.5, 0.25)
    return _core.DirectModel(matrices, [], None, method, 1e-9, 10)


def direct_run(n=1, **changes):
    return _core.DirectRun(grid(**changes), np.zeros(n), np.zeros(n), np.arange(n, dtype=np.int64))


def test_table_values_at_nan_time_is_nan():
    # Used to panic: NaN compares false with every sample, and the search fell to index -1.
    table = _core.TimeFunction.table(f64(0.0, 1.0), f64(0.0, 2.0), False)
    values = table.values(f64(np.nan, 0.5, np.inf, -np.inf))
    assert np.isnan(values[0])
    assert values[1:].tolist() == [1.0, 0.0, 0.0]


def test_element_stiffness_velocity_of_wrong_length():
    # Used to panic: `v` was indexed at the element's dofs, checked against `x` only.
    spring = _core.Spring(1, None, k=1.0, k3=0.0)
    with pytest.raises(ValueError, match="`v` has length 1, expected 2"):
        _core.element_stiffness([spring], f64(0.0, 0.0), f64(0.0), 0.0)


def test_output_count_that_overflows():
    # `width * n_cols` used to wrap (a panic with overflow checks). The output maps must now
    # have `n_cols` columns, so a count no array can have is refused when they are made.
    with pytest.raises(ValueError, match=r"`map` must have shape \(any, 18446744073709551615\)"):
        _core.Outputs(np.zeros((0, 2)), np.zeros((0, 2)), 2**64 - 1)
    with pytest.raises(ValueError, match=r"`loads` must have shape \(any, 2\), got \(0, 3\)"):
        _core.Outputs(np.zeros((4, 2)), np.zeros((0, 3)), 2)


@pytest.mark.parametrize("route", ["uncoupled", "direct"])
def test_step_count_whose_saved_instants_overflow(route):
    # The count of saved instants, n_steps + 1, used to wrap to 0: the run then stepped
    # 2**64 times saving nothing (with overflow checks, a panic). Now: too much memory.
    n_steps, dt = 2**64 - 1, 1e-300
    with pytest.raises(ValueError, match="`save_every` is too small"):
        if route == "uncoupled":
            modal_model(1).run(modal_run(1, n_steps=n_steps, dt=dt))
        else:
            direct_model(1).run(direct_run(1, n_steps=n_steps, dt=dt), [])


def test_direct_end_time_that_overflows():
    # Used to run on infinite times (and report a singular matrix): refused like the modal
    # routes refuse it.
    with pytest.raises(ValueError, match="`t_end` is too large"):
        direct_model(1).run(direct_run(1, t0=1e308, dt=1e307, n_steps=10), [])


def test_first_order_elements_with_mode_shapes_of_wrong_length():
    # The coupled route's elements used to read `phi` without checking its length against
    # `n_dof x n_modes` (rows past its end for a caller of the core). The model now checks
    # it when made, on every route.
    spring = [_core.Spring(0, None, k=1.0, k3=1.0)]
    corrector = _core.Corrector(spring, np.zeros((4, 4)), 1e-9, 10)
    with pytest.raises(ValueError, match=r"`phi` must have shape \(any, 2\), got \(1, 3\)"):
        modal_model(2, first_order_route(2, 2, corrector), phi=np.array([[1.0, 0.5, 0.25]]))
    # A 2-D array of the right size but the wrong shape is refused too (it used to be read
    # as another shape of the same length).
    with pytest.raises(ValueError, match=r"`phi` must have shape \(any, 2\), got \(2, 1\)"):
        modal_model(2, first_order_route(2, 2, corrector), phi=np.array([[1.0], [0.5]]))


def test_fortran_ordered_dense_matrix():
    # Used to be read row-major, i.e. transposed, without a word.
    a = np.asfortranarray([[1.0, 2.0], [3.0, 4.0]])
    with pytest.raises(ValueError, match="C-contiguous"):
        _core.Matrix.dense(a)
    assert _core.Matrix.dense(np.ascontiguousarray(a)) is not None
