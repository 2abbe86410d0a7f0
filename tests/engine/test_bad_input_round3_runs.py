"""Bad input to runs and what they return (issue 38, third bad-input campaign): events,
``t_eval``, ``Solution.at``, ``base_shear``, ``solve_many``, ``property_bounds``, a dense
eigendecomposition too large for the memory, and a Bouc-Wen element whose increments need
more substeps than the bound.

Each case of the issue is a test: the input is refused by name (a ``ValueError`` or
``TypeError`` whose message quotes the parameter), or a run that cannot finish stops with a
``SolverError`` naming the element, never an internal exception, a crash or a run that
takes minutes.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.integrate import solve_ivp

import duhamel
import duhamel._engine.memory as memory
from duhamel import events
from duhamel.ensemble import property_bounds, solve_many


@pytest.fixture
def oscillator() -> duhamel.System:
    return duhamel.System(np.eye(1), 4.0 * np.eye(1))


@pytest.fixture
def shear_building() -> duhamel.System:
    """Two storeys under a support acceleration."""
    t = np.linspace(0.0, 2.0, 201)
    s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], zeta=0.05)
    return s.add_load(duhamel.loads.BaseAcceleration(np.ones(2), t, np.sin(5.0 * t)))


# -- events -----------------------------------------------------------------------------------


def test_drift_of_a_dof_against_itself_is_refused():
    # events.drift(1, 1, 0.01) was accepted and never fired (the drift is always 0)
    with pytest.raises(ValueError, match=r"^`j` must differ from `i` \(both are 1\)"):
        events.drift(1, 1, 0.01)
    with pytest.raises(ValueError, match="`j` must differ from `i`"):
        events.drift(np.int64(2), 2, 0.01)
    assert events.drift(1, 0, 0.01).j == 0 and events.drift(1, None, 0.01).j is None


@pytest.mark.parametrize("integrator", [duhamel.Semianalytic(), duhamel.Newmark()])
@pytest.mark.parametrize("terminal", [False, True])
@pytest.mark.parametrize(
    ("fn", "said"),
    [
        (lambda t, x, v: np.array([x[0], v[0]]), "shape (2,)"),
        (lambda t, x, v: [x[0], x[0], x[0]], "shape (3,)"),
        (lambda t, x, v: "x", "real numbers, got str"),
        (lambda t, x, v: None, "real numbers, got NoneType"),
    ],
)
def test_an_event_function_must_return_one_number(oscillator, integrator, terminal, fn, said):
    # an event returning shape (2,) leaked "only 0-dimensional arrays can be converted"
    ev = duhamel.Event(fn, terminal=terminal, name="e")
    with pytest.raises(ValueError, match=rf"^event 'e': `fn` must return .*{said.split()[0]}"):
        duhamel.solve(oscillator, integrator, t_end=1.0, dt=0.1, x0=[1.0], events=[ev])


def test_an_unnamed_event_and_a_vectorized_one_are_named(oscillator):
    ev = duhamel.Event(lambda t, x, v: x)  # x has shape (1,): one number, accepted
    sol = duhamel.solve(oscillator, duhamel.Semianalytic(), t_end=2.5, dt=0.1, x0=[1.0],
                        events=[ev])  # fmt: skip
    # cos(2 t) = 0 at t = pi / 4 and 3 pi / 4 (exact on the linear route)
    assert [o.time for o in sol.events] == pytest.approx([np.pi / 4, 3 * np.pi / 4], abs=1e-12)
    bad = duhamel.Event(lambda t, x, v: np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"^an event: `fn` must return one number"):
        duhamel.solve(oscillator, duhamel.Semianalytic(), t_end=1.0, dt=0.1, events=[bad])
    vec = duhamel.Event(lambda t, x, v: x, vectorized=True, name="v")  # (n, 1), not (n,)
    with pytest.raises(ValueError, match=r"^event 'v': `fn` must return shape \(11,\)"):
        duhamel.solve(oscillator, duhamel.Semianalytic(), t_end=1.0, dt=0.1, events=[vec])
    with pytest.raises(TypeError, match="`vectorized` must be True or False"):
        duhamel.Event(lambda t, x, v: 0.0, vectorized="no")


# -- what a run returns -----------------------------------------------------------------------


@pytest.mark.parametrize("integrator", [duhamel.Semianalytic(), duhamel.Newmark()])
def test_an_empty_t_eval_is_refused(oscillator, integrator):
    # solve(t_eval=[]) returned a Solution without rows ("zero-size array" downstream)
    for empty in ([], np.array([]), ()):
        with pytest.raises(ValueError, match=r"^`t_eval` is empty"):
            duhamel.solve(oscillator, integrator, t_end=1.0, dt=0.1, x0=[1.0], t_eval=empty)


def test_solution_at_refuses_strings(oscillator):
    # sol.at('0.5') was read through float()
    sol = duhamel.solve(oscillator, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0],
                        dense=True)  # fmt: skip
    with pytest.raises(TypeError, match=r"^`t` must contain real numbers, got dtype string"):
        sol.at("0.5")
    with pytest.raises(TypeError, match=r"^`t`"):
        sol.at(["0.5", "0.6"])
    x, _ = sol.at(0.5)
    assert x[0] == pytest.approx(np.cos(1.0), abs=1e-14)


def test_base_shear_refuses_storeys_beyond_the_model(shear_building):
    # IndexError from base_shear(storeys=[7]); a negative dof counted from the end
    sol = duhamel.solve(shear_building, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
    for storeys, dof in (([7], 7), ([0, -1], -1), ([[0, 5]], 5)):
        with pytest.raises(ValueError, match=rf"^`storeys`: dof {dof} is not a dof of the model"):
            sol.base_shear(storeys=storeys)
    shears = sol.base_shear(storeys=[0, 1])
    assert np.array_equal(shears[:, 0], sol.base_shear())


@pytest.mark.parametrize(
    ("direction", "kind", "said"),
    [
        ("x", TypeError, "the string 'x'"),
        (["1", "1"], TypeError, "real numbers"),
        ([1.0], ValueError, "over the 2 dofs"),
        ([1.0, float("nan")], ValueError, "finite vector"),
    ],
)
def test_base_shear_direction_is_refused_by_name(shear_building, direction, kind, said):
    # base_shear(direction='x') leaked "could not convert string to float"
    sol = duhamel.solve(shear_building, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
    with pytest.raises(kind, match=f"^`direction`.*{said}"):
        sol.base_shear(direction=direction)


# -- ensembles --------------------------------------------------------------------------------


@pytest.mark.parametrize("params", [None, 5, 2.5, "abc", b"ab"])
def test_solve_many_params_must_be_an_iterable(oscillator, params):
    # "'NoneType' object is not iterable"
    with pytest.raises(TypeError, match=r"^`params` must be an iterable"):
        solve_many(lambda p: oscillator, params, duhamel.Semianalytic(), t_end=1.0, dt=0.1)


@pytest.mark.parametrize("made", ["abc", None, 3, ("abc", {})])
@pytest.mark.parametrize("basis", [None, "first"])
def test_make_system_must_return_a_model(made, basis):
    # a string leaked "'str' object has no attribute 'modal'"
    with pytest.raises(TypeError, match=r"^`make_system` must return a duhamel.System") as info:
        solve_many(lambda p: made, [1.0], duhamel.Semianalytic(), t_end=1.0, dt=0.1,
                   basis=basis)  # fmt: skip
    assert "case 0" in " ".join(getattr(info.value, "__notes__", []))
    with pytest.raises(TypeError, match=r"^`make_system` must be callable, got str"):
        solve_many("abc", [1.0], duhamel.Semianalytic(), t_end=1.0, dt=0.1)


@pytest.mark.parametrize(
    ("grid", "said"),
    [
        ({"t_end": 1.0, "dt": -0.01}, "`dt` must be positive"),
        ({"t_end": 1.0, "dt": "0.01"}, "`dt` must be a real number"),
        ({"t_end": 0.0, "dt": 0.01}, "`t_end` .* must be at least one step"),
        ({"t_end": float("nan"), "dt": 0.01}, "`t_end` must be finite"),
        ({"t_end": 1.0, "dt": 0.01, "t0": "0"}, "`t0` must be a real number"),
    ],
)
def test_solve_many_checks_its_grid_without_cases(oscillator, grid, said):
    # solve_many([], dt=-0.01) was accepted (no run checked it)
    for params in ([], [1.0]):
        with pytest.raises((ValueError, TypeError), match=f"^{said}"):
            solve_many(lambda p: oscillator, params, duhamel.Semianalytic(), **grid)


@pytest.mark.parametrize(
    ("lambdas", "kind", "said"),
    [
        ({"mu": ("0.8", "1.3")}, TypeError, r"`lambdas\['mu'\]` must be a real number, got str"),
        ({"mu": "0.8"}, TypeError, r"`lambdas\['mu'\]` must be a \(lower, upper\) pair"),
        ({"mu": (0.8, 1.3, 2.0)}, TypeError, "got 3 values"),
        ({"mu": (0.8, float("inf"))}, ValueError, "must be finite"),
        ({"mu": (1.3, 0.8)}, ValueError, "0 < lower <= upper"),
        ({1: (0.8, 1.3)}, TypeError, "`lambdas` keys must be property names"),
    ],
)
def test_property_bounds_refuses_bad_factors(lambdas, kind, said):
    s = duhamel.System(np.eye(1), np.zeros((1, 1)))
    s = s.add(duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=9.81))
    with pytest.raises(kind, match=said):
        property_bounds(s, lambdas)
    models = property_bounds(s, {"mu": (0.8, 1.3)})
    assert models["lower"].elements[0].mu == pytest.approx(0.04, rel=1e-15)


# -- a dense eigendecomposition beyond the memory ---------------------------------------------


def _lattice(n: int, **damping) -> duhamel.System:
    k = sp.diags([2.0 * np.ones(n), -np.ones(n - 1), -np.ones(n - 1)], [0, -1, 1], format="csr")
    return duhamel.System(sp.identity(n, format="csr"), k, **damping)


def test_modal_damping_on_a_direct_integrator_beyond_the_memory_is_refused(monkeypatch):
    # Newmark() on a 24,000-dof sparse lattice with zeta = 0.05 asked scipy.linalg.eigh for
    # every mode and ended the process (segmentation fault). The limit is half the memory
    # available; 300 dofs need 12 dense 300 x 300 arrays, 8.64 MB: just over and just under.
    n = 300
    need = 12 * 8.0 * n * n
    monkeypatch.setattr(memory, "available_memory", lambda: int(2 * need * 0.999))
    with pytest.raises(ValueError, match=r"^`zeta` \(modal damping ratios\) on a direct") as info:
        duhamel.solve(_lattice(n, zeta=0.05), duhamel.Newmark(), t_end=0.02, dt=0.01)
    msg = str(info.value)
    assert "300-dof model" in msg and "8.24 MiB" in msg and "Rayleigh damping" in msg
    assert "duhamel.Semianalytic(modes=...)" in msg and "memory available (16.5 MiB)" in msg
    # what it advises runs: Rayleigh damping stays sparse, the semi-analytic route asks for
    # the lowest modes only
    sol = duhamel.solve(_lattice(n, rayleigh=(0.0, 0.01)), duhamel.Newmark(), t_end=0.02,
                        dt=0.01, x0=np.full(n, 1e-3))  # fmt: skip
    assert np.all(np.isfinite(sol.x))
    sol = duhamel.solve(_lattice(n, zeta=0.05), duhamel.Semianalytic(modes=20), t_end=0.02,
                        dt=0.01, x0=np.full(n, 1e-3))  # fmt: skip
    assert np.all(np.isfinite(sol.x))
    monkeypatch.setattr(memory, "available_memory", lambda: int(2 * need * 1.001))
    sol = duhamel.solve(_lattice(n, zeta=0.05), duhamel.Newmark(), t_end=0.02, dt=0.01,
                        x0=np.full(n, 1e-3))  # fmt: skip
    assert np.all(np.isfinite(sol.x))


def test_every_mode_of_a_large_model_beyond_the_memory_is_refused(monkeypatch):
    n = 300
    need = 6 * 8.0 * n * n
    monkeypatch.setattr(memory, "available_memory", lambda: int(2 * need * 0.999))
    with pytest.raises(ValueError, match=r"^`modes` = 300 of the 300-dof model asks for a full"):
        duhamel.solve(_lattice(n, zeta=0.05), duhamel.Semianalytic(), t_end=0.02, dt=0.01)
    with pytest.raises(ValueError, match=r"^`modes` = 300 of the 300-dof model"):
        _lattice(n).modal()
    assert _lattice(n).modal(10).n_modes == 10  # shift-invert Lanczos: no dense eigh
    monkeypatch.setattr(memory, "available_memory", lambda: int(2 * need * 1.001))
    assert _lattice(n).modal().n_modes == n


# -- a Bouc-Wen element beyond the substep bound ----------------------------------------------


def _bouc_wen(**shape) -> duhamel.System:
    s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
    s.add(duhamel.elements.BoucWen(0, None, k=1.0, fy=1e-300, alpha=0.0, **shape))
    return s.add_load(duhamel.loads.Harmonic(0, 1.0, omega=3.0))


@pytest.mark.parametrize("integrator", [duhamel.Semianalytic(), duhamel.Newmark()])
@pytest.mark.parametrize(
    ("shape", "step"),
    [
        # the element: it unloads from saturation with g ~ 1e-16 (beta ~ 0), which
        # rounds away at every substep (a million substeps per evaluation before)
        ({"beta": 1e-300, "n": 1.66}, None),
        # beta = gamma = 1e-300: z saturates at 3.5e180, at the first step
        ({"beta": 1e-300, "gamma": 1e-300, "n": 1.66}, 1),
    ],
)
def test_a_bouc_wen_beyond_the_substep_bound_stops_naming_it(integrator, shape, step):
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(_bouc_wen(**shape), integrator, t_end=3.0, dt=0.01)
    err = info.value
    assert err.reason == "domain"
    assert str(err).startswith("BoucWen (dofs [0]): the deformation increment from")
    assert "more than the bound of 1e6 RK4 substeps" in str(err)
    assert step is None or err.step == step
    # until it stopped, the element's force (at most 1e-300 fy z) changed nothing: the
    # history is the linear oscillator's x'' + 0.1 x' + x = sin(3 t)
    t = err.partial.t
    if t.size == 1:
        assert t[0] == 0.0 and err.partial.x[0, 0] == 0.0
        return
    ref = solve_ivp(lambda _, y: [y[1], np.sin(3.0 * _) - 0.1 * y[1] - y[0]], (0.0, t[-1]),
                    [0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-14, method="DOP853")  # fmt: skip
    assert np.max(np.abs(err.partial.x[:, 0] - ref.y[0])) < 2e-4 * np.max(np.abs(ref.y[0]))


def test_an_initial_deformation_beyond_the_substep_bound_is_reported_at_the_first_step():
    s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
    s.add(duhamel.elements.BoucWen(0, None, k=1.0, fy=1e-300, alpha=0.0, beta=1e-300, gamma=1e-300,
                                   n=1.66))  # fmt: skip
    with pytest.raises(duhamel.SolverError, match=r"^BoucWen \(dofs \[0\]\)") as info:
        duhamel.solve(s, duhamel.Newmark(), t_end=0.1, dt=0.01, x0=[0.01])
    assert info.value.reason == "domain"
