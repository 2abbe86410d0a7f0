"""Two builds of duhamel on the same cases, interleaved: is a change slower? Do they give the
same numbers, bit for bit (``--check``)?

Each case runs in a fresh subprocess per build and repeat, the builds alternating (old, new,
old, new, ...), so the machine's load hits both alike; the table gives the best loop time
(``Solution.stats.wall_time``) of each and their ratio. A build is a directory holding the
``duhamel`` package with its compiled ``_core`` (e.g. a ``git worktree`` of an older commit
with the extension copied in, and ``python/`` of this checkout)::

    .venv/bin/python benchmarks/compare.py --old ../baseline/python --new python --repeats 7

The cases are the engine's routes: the uncoupled linear loop (every step saved, and the
kernel alone), the closed-form and the Newton Duffing step, a 5-mode Newton chain, a
gyroscopic rotor on the exact first-order background (linear, and with a rub), and Newmark
on a 20-dof chain.

``--check`` (issue 22: every route gives the same numbers as before) runs instead a set of
small cases covering every route under both builds, each build in one subprocess (the two
in parallel), saves each case's arrays to .npz in a temporary directory and compares them
old against new bit for bit (dtype, shape and bytes: NaN-aware, signed zeros told apart).
It prints a table case / arrays / identical? and exits 1 on any difference (2 when a
build's worker fails)::

    .venv/bin/python benchmarks/compare.py --check --old ../baseline/python --new python

Per case it keeps ``t, x, v, a, dofs``, the modal history (``q, v, p, pseudo_force``), the
element histories (``x, v, force``) and the stats' counters (steps, modes, Newton
iterations, closed-form steps, factorisations, subdivisions, coupling, eigenvector
condition); a case that raises keeps its exception's type and message. The cases (public
API only, so that they run on a build whose private modules moved): the uncoupled linear
route (modal damping, Rayleigh, a classical damping matrix, ``modes=3`` with and without the
static correction, ``save_every``/``dofs``/``t0``/``x0``/``v0``, a continued run); the
first-order route (non-classical ``C`` without and with a Bouc-Wen element, a
``LinearCoupling`` cross stiffness, a gyroscopic rotor without and with a rub) and
``coupling="pseudo-force"``; the pseudo-force route: Duffing closed form and Newton, a
``Spring`` with ``k3`` under ``linear_parts`` auto/background/pseudo-force, ``Polynomial``
with ``Damper``, ``Bilinear``, ``BoucWen``, ``Gap``, ``ViscousDamper``,
``FrictionPendulum``, ``Contact``, ``Callable`` elements (plain, with a Jacobian, with
state), ``Callable`` loads, schemes a/b/c x the three quadratures, ``modal-newton``,
``modes=3`` with and without the static correction, step subdivision (a stiff friction
law, a stiff gap), mass laws (exponential, harmonic, tabulated; eliminated and estimated
acceleration), a rotor run-up (``LinearRunUp`` with its ``Unbalance``, with and without a
rub) and a coupling scaled by a run-up; ``Newmark``, ``HHT``, ``GeneralizedAlpha``,
``CentralDifference``, ``CubicHermite`` on dense and sparse models, without and with a
``Bilinear``; a streamed run (``store=``, when zarr is installed) and ``duhamel.resume``;
``duhamel.ensemble.solve_many`` in threads; ``response_spectrum``, ``rotd`` and
``ductility_spectrum``; and ``duhamel reproduce`` (every example but the timing one,
``cpu``), whose report's table numbers are compared with their timing fragments left out.
Where a build has ``duhamel.prepare``, every ``solve`` case also runs as
``prepare(...).run(...)`` (``+prepared``) and as a second run of the same ``Prepared``
(``+prepared-again``), compared with the old build's twin or, when the old build has no
``prepare``, with its plain ``solve``. ``--cases a,b`` runs only those cases.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import subprocess
import sys

import numpy as np

CASE = r"""
import json, sys, time
import numpy as np
import duhamel
from duhamel import elements as E, loads as L

def where(cls, *dofs):
    # a device's dofs as the build spells them: `dofs`, else the previous release's `dof_x`...
    import inspect
    if "dofs" in inspect.signature(cls).parameters:
        return {"dofs": dofs}
    return dict(zip(("dof_x", "dof_y", "dof_z"), dofs, strict=False))

def chain(n, k=1e6):
    return k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))

case = sys.argv[1]
if case.startswith("linear"):
    n = 100
    K = chain(n); K[-1, -1] = 1e6
    s = duhamel.System(np.eye(n), K, zeta=0.02)
    s.add_load(L.Harmonic(n - 1, amplitude=1000.0, omega=4 * np.pi))
    s.add_load(L.Step(49, amplitude=500.0))
    steps = 100_000
    save = steps if case == "linear-kernel" else 1
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(), t_end=steps * 1e-3, dt=1e-3,
                                dofs=[n - 1], threads=1, save_every=save)
elif case.startswith("duffing"):
    s = duhamel.System(np.eye(1), np.eye(1)).add(E.Cubic(0, k3=4.0))
    steps = 1_000_000 if case == "duffing" else 200_000
    solver = "newton" if case == "duffing-newton" else "auto"
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(solver=solver), t_end=steps * 0.0628,
                                dt=0.0628, x0=[1.0])
elif case == "chain-newton":
    n = 20
    s = duhamel.System(np.eye(n), chain(n, 1e4), zeta=0.02)
    for d in (3, 8, 13, 18):
        s.add(E.Spring(d, None, k=0.0, k3=1e7))
    s.add_load(L.Harmonic(n - 1, amplitude=50.0, omega=20.0))
    steps = 100_000
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(modes=5), t_end=steps * 1e-3,
                                dt=1e-3)
elif case.startswith("rotor"):
    from duhamel import rotor as R
    steel = R.Material(E=211e9, rho=7810.0, nu=0.3)
    shafts = [R.Shaft(0.1, 0.05, material=steel) for _ in range(12)]
    disks = [R.Disk.from_geometry(6, 0.07, 0.28, 0.05, steel)]
    bearings = [R.Bearing(0, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3, kxy=1e6, kyx=-1e6),
                R.Bearing(12, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3)]
    machine = R.Rotor(shafts, disks, bearings, rayleigh=(1.0, 1e-5))
    speed = R.rpm(3000)
    s = machine.system(speed, loads=[R.Unbalance(6, 1e-4, speed)])
    if case == "rotor-rub":
        dx, dy = machine.dof(6, "x"), machine.dof(6, "y")
        s.add(E.Contact(**where(E.Contact, dx, dy), clearance=2e-6, stiffness=1e7, friction=0.1))
    steps = 100_000 if case == "rotor" else 20_000
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(), t_end=steps * 1e-4, dt=1e-4,
                                threads=1)
elif case == "newmark":
    n = 20
    s = duhamel.System(np.eye(n), chain(n, 1e4), zeta=0.02)
    s.add_load(L.Harmonic(n - 1, amplitude=50.0, omega=20.0))
    steps = 100_000
    run = lambda: duhamel.solve(s, duhamel.Newmark(), t_end=steps * 1e-3, dt=1e-3)
run()  # warm-up: first calls of a process are slower (page faults, caches)
sol = run()
print(json.dumps({"wall": sol.stats.wall_time, "steps": sol.stats.steps,
                  "route": sol.stats.coupling}))
"""

CASES = [
    "linear",
    "linear-kernel",
    "duffing",
    "duffing-newton",
    "chain-newton",
    "rotor",
    "rotor-rub",
    "newmark",
]


def measure(path: str, case: str) -> float:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(path), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run(
        [sys.executable, "-c", CASE, case], env=env, capture_output=True, text=True, check=True
    )
    return float(json.loads(out.stdout.strip().splitlines()[-1])["wall"])


# ------------------------------------------------------------------------------------------
# --check: the same numbers, bit for bit
# ------------------------------------------------------------------------------------------
#
# The worker below runs in a subprocess per build (``compare.py --worker OUT`` with the
# build first on PYTHONPATH). It uses only the public API (``duhamel.solve``, ``System``,
# ``elements``, ``loads``, ``mass``, ``speed``, ``rotor``, ``ensemble``, ``spectra``,
# ``resume``, and ``prepare`` where the build has it), so that it runs unchanged on a build
# whose private modules moved. Every case returns named arrays, saved to OUT/<case>.npz; a
# case that raises saves its exception's type and message instead (equal on both builds
# when they refuse the same input alike).


class Unsupported(Exception):
    """A solve option that ``Prepared.run`` does not take (the case has no prepared twin)."""


def _chain(n, k=1e4, fixed_free=True):
    K = k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    if fixed_free:
        K[-1, -1] = k
    return K


def _record(n, t_end=4.0, dt=0.01, amplitude=3.0):
    from duhamel import loads as L

    t = np.arange(0.0, t_end + dt / 2, dt)
    a = amplitude * np.sin(7.0 * t) * np.exp(-0.3 * t) + 0.5 * np.sin(23.0 * t)
    return L.BaseAcceleration(np.ones(n), t=t, values=a)


def _linear(damping="zeta", n=6):
    import duhamel
    from duhamel import loads as L

    K = _chain(n)
    kw = {"zeta": 0.03} if damping == "zeta" else {}
    if damping == "rayleigh":
        kw = {"rayleigh": (0.2, 2e-4)}
    if damping == "classical":
        kw = {"C": 0.2 * np.eye(n) + 2e-4 * K}
    if damping == "nonclassical":
        C = 0.2 * np.eye(n) + 2e-4 * K
        C[0, 0] += 30.0
        kw = {"C": C}
    s = duhamel.System(np.eye(n), K, **kw)
    s.add_load(L.Harmonic(n - 1, amplitude=50.0, omega=11.0, phase=0.3))
    s.add_load(L.Step(n // 2, amplitude=20.0))
    s.add_load(L.Tabulated(1, t=[0.0, 0.5, 1.0, 3.0], values=[0.0, 30.0, -10.0, 0.0]))
    s.add_load(_record(n))
    return s


def where(cls, *dofs):
    """A device's dofs as the build spells them: `dofs` (this release), else `dof_x`...
    (the previous one, which has no `dofs`): both builds run the same case, unwarned."""
    import inspect

    if "dofs" in inspect.signature(cls).parameters:
        return {"dofs": dofs}
    return dict(zip(("dof_x", "dof_y", "dof_z"), dofs, strict=False))


def _with(system, *elements):
    for e in elements:
        system.add(e)
    return system


def _callable_force(x, v, t):
    r = 2e3 * np.tanh(x[0] / 1e-3) + 5.0 * v[1] * abs(v[1])
    return np.array([r, -r])


def _callable_jacobian(x, v, t):
    d = 2e3 / 1e-3 * (1.0 - np.tanh(x[0] / 1e-3) ** 2)
    e = 10.0 * abs(v[1])
    return np.array([[d, 0.0], [-d, 0.0]]), np.array([[0.0, e], [0.0, -e]])


def _elastoplastic(x, v, t, state, k=4e3, fy=20.0):
    plastic = state[1]
    trial = k * (x[0] - plastic)
    if abs(trial) > fy:
        plastic = x[0] - np.sign(trial) * fy / k
        trial = np.sign(trial) * fy
    return np.array([trial]), np.array([x[0], plastic])


def _friction(x, v, t):
    return np.array([0.1 * 9.81 * 3.0 * np.tanh(v[0] / 1e-4)])


def _rotor(speed, rub=False, steps=2000):
    from duhamel import elements as E
    from duhamel import rotor as R

    steel = R.Material(E=211e9, rho=7810.0, nu=0.3)
    shafts = [R.Shaft(0.1, 0.05, material=steel) for _ in range(6)]
    disks = [R.Disk.from_geometry(3, 0.07, 0.28, 0.05, steel)]
    bearings = [
        R.Bearing(0, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3, kxy=1e6, kyx=-1e6),
        R.Bearing(6, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3),
    ]
    machine = R.Rotor(shafts, disks, bearings, rayleigh=(1.0, 1e-5))
    s = machine.system(speed, loads=[R.Unbalance(3, 1e-4)])
    if rub:
        dx, dy = machine.dof(3, "x"), machine.dof(3, "y")
        s.add(E.Contact(**where(E.Contact, dx, dy), clearance=2e-6, stiffness=1e7, friction=0.1))
    return s


def _dump(sol, prefix=""):
    """A Solution's numbers: t, x, v, a, dofs, the modal history, the element histories and
    the stats' counters (not its timings)."""
    out = {}
    for name in ("t", "x", "v", "a", "dofs"):
        out[prefix + name] = np.asarray(getattr(sol, name))
    modal = getattr(sol, "modal", None)
    if modal is not None:
        for name in ("q", "v", "p", "pseudo_force"):
            try:
                out[f"{prefix}modal.{name}"] = np.asarray(getattr(modal, name))
            except Exception as e:  # recorded and compared
                out[f"{prefix}modal.{name}"] = np.array(f"{type(e).__name__}: {e}")
    for k, h in enumerate(getattr(sol, "elements", ()) or ()):
        for name in ("x", "v", "force"):
            out[f"{prefix}element{k}.{name}"] = np.asarray(getattr(h, name))
    stats = sol.stats
    for name in (
        "steps",
        "modes",
        "newton_iterations",
        "closed_form_steps",
        "factorizations",
        "subdivided_steps",
        "subdivision_depth",
        "coupling",
        "eigenvector_condition",
    ):
        if hasattr(stats, name):
            value = getattr(stats, name)
            out[f"{prefix}stats.{name}"] = np.array("None" if value is None else value)
    return out


def _cases():
    """name -> function(solve) returning named arrays; `solve` is ``duhamel.solve`` or its
    ``prepare(...).run(...)`` twin."""
    import scipy.sparse as sp

    import duhamel
    from duhamel import elements as E
    from duhamel import loads as L
    from duhamel import mass as Ms
    from duhamel import speed as S

    SA = duhamel.Semianalytic
    run = {"t_end": 2.0, "dt": 0.01}
    x0 = [0.001, 0.0, -0.002, 0.0, 0.001, 0.003]
    cases = {}

    def case(name, make, integrator, **kw):
        def f(solve):
            return _dump(solve(make(), integrator, **{**run, **kw}))

        cases[name] = f

    # -- the uncoupled linear route
    case("linear-zeta", _linear, SA(), x0=x0)
    case("linear-rayleigh", lambda: _linear("rayleigh"), SA(), v0=x0)
    case("linear-classical-C", lambda: _linear("classical"), SA())
    long = lambda: _linear(n=14)  # noqa: E731 - a basis of 3 modes + 4 load vectors < 14 dofs
    case("linear-modes3", long, SA(modes=3))
    case("linear-modes3-static", long, SA(modes=3, static_correction=True))
    case("linear-save-dofs-t0", _linear, SA(), save_every=7, dofs=[0, 4], t0=0.5, x0=x0, v0=x0)

    def continued(solve):
        first = solve(_linear(), SA(), t_end=1.0, dt=0.01, x0=x0)
        rest = solve(_linear(), SA(), t0=float(first.t[-1]), t_end=2.0, dt=0.01,
                     x0=first.x[-1], v0=first.v[-1])  # fmt: skip
        return {**_dump(first, "first."), **_dump(rest, "rest.")}

    cases["linear-continued"] = continued
    # -- the first-order route (exact coupled background) and its pseudo-force alternative
    case("first-order-C", lambda: _linear("nonclassical"), SA(), x0=x0)
    case("first-order-C-bouc-wen",
         lambda: _with(_linear("nonclassical"), E.BoucWen(1, 2, k=4e3, fy=30.0, alpha=0.05)),
         SA(), x0=x0)  # fmt: skip
    case("coupling-pseudo-force", lambda: _linear("nonclassical"), SA(coupling="pseudo-force"))
    cross = np.zeros((6, 6))
    cross[0, 1], cross[1, 0] = 2e3, -2e3
    case("first-order-cross-K", lambda: _with(_linear(), E.LinearCoupling(K=cross)), SA())
    case("rotor-gyroscopic", lambda: _rotor(300.0), SA(), t_end=0.05, dt=1e-4)
    case("rotor-gyroscopic-rub", lambda: _rotor(300.0, rub=True), SA(), t_end=0.02, dt=1e-4)
    # -- the pseudo-force route: elements
    duffing = lambda: _with(duhamel.System(np.eye(1), np.eye(1)), E.Cubic(0, k3=4.0))  # noqa: E731
    case("duffing-closed-form", duffing, SA(), t_end=60.0, dt=0.0628, x0=[1.0])
    case("duffing-newton", duffing, SA(solver="newton"), t_end=60.0, dt=0.0628, x0=[1.0])
    ray = lambda: _linear("rayleigh")  # noqa: E731
    for parts in ("auto", "background", "pseudo-force"):
        case(f"spring-k3-linear-parts-{parts}",
             lambda: _with(ray(), E.Spring(2, 3, k=3e3, k3=1e9), E.Spring(0, None, k=1e3, k3=5e8)),
             SA(linear_parts=parts), x0=x0)  # fmt: skip
    case("spring-k3-zeta", lambda: _with(_linear(), E.Spring(2, 3, k=3e3, k3=1e9)), SA(), x0=x0)
    case("polynomial-damper",
         lambda: _with(_linear(), E.Polynomial(5, coefficients=[0.0, 100.0, 0.0, 3e8]),
                       E.Damper(1, 4, c=20.0)),
         SA())  # fmt: skip
    for name, element in {
        "bilinear": E.Bilinear(0, None, k=5e3, fy=20.0, alpha=0.05),
        "bilinear-pair": E.Bilinear(2, 3, k=5e3, fy=10.0, alpha=0.0),
        "bouc-wen": E.BoucWen(1, 2, k=4e3, fy=15.0, alpha=0.1, n=2.0),
        "gap": E.Gap(5, None, gap=0.002, k=1e5),
        "viscous-damper": E.ViscousDamper(0, 1, c=50.0, exponent=0.4),
        "friction-pendulum": E.FrictionPendulum(
            **where(E.FrictionPendulum, 4, 5), radius=2.0, mu=0.06, weight=2e3
        ),
        "contact": E.Contact(**where(E.Contact, 4, 5), clearance=1e-3, stiffness=1e6, friction=0.2),
    }.items():
        case(f"element-{name}", lambda element=element: _with(_linear(), element), SA(), x0=x0)

    # -- one mode (the one-dof device, one kept mode of a two-dof frame): its own solver
    def one_dof(element, m=10.0, k=1e4):
        s = duhamel.System(m * np.eye(1), k * np.eye(1), zeta=0.05)
        t = np.linspace(0.0, 3.0, 601)
        a = 30.0 * np.sin(7.0 * t) * np.sin(1.3 * t)
        s.add_load(L.BaseAcceleration(np.ones(1), t=t, values=a))
        return _with(s, element)

    for name, element in {
        "bilinear": E.Bilinear(0, None, k=1e4, fy=60.0, alpha=0.05),
        "gap": E.Gap(0, None, gap=0.004, k=3e4),
        "viscous-damper": E.ViscousDamper(0, None, c=200.0, exponent=0.4),
        "friction-pendulum": E.FrictionPendulum(
            **where(E.FrictionPendulum, 0, None), radius=2.0, mu=0.05, weight=98.0
        ),
        "bouc-wen": E.BoucWen(0, None, k=1e4, fy=60.0, alpha=0.1, n=2.0),
    }.items():
        make = lambda element=element: one_dof(element)  # noqa: E731
        case(f"one-mode-{name}", make, SA(), t_end=3.0, dt=0.005, save_every=3)
    bilinear1 = lambda: one_dof(E.Bilinear(0, None, k=1e4, fy=60.0, alpha=0.05))  # noqa: E731
    for scheme in ("a", "c"):
        for quadrature in ("parabolic", "exact"):
            integrator = SA(scheme=scheme, quadrature=quadrature)
            case(f"one-mode-bilinear-{scheme}-{quadrature}", bilinear1, integrator, t_end=3.0)
    case("one-mode-stiff-gap",
         lambda: one_dof(E.Gap(0, None, gap=0.002, k=1e8)), SA(), t_end=3.0, dt=0.01)  # fmt: skip

    def frame():
        s = duhamel.System(np.diag([2.0, 1.0]), _chain(2), zeta=0.03)
        return _with(s, E.Bilinear(0, 1, k=3e3, fy=5.0, alpha=0.1))

    case("one-mode-of-two", frame, SA(modes=1, static_correction=False), x0=[0.004, 0.01])
    case("callable-element",
         lambda: _with(_linear(), E.Callable(fn=_callable_force, dofs=[2, 3])), SA())  # fmt: skip
    case("callable-element-jacobian",
         lambda: _with(_linear(), E.Callable(fn=_callable_force, dofs=[2, 3],
                                             jacobian=_callable_jacobian)),
         SA())  # fmt: skip
    epp = E.Callable(fn=_elastoplastic, dofs=[0], state=[0.0, 0.0])
    case("callable-element-state", lambda: _with(_linear(), epp), SA())

    def callable_load():
        s = _with(_linear(), E.Cubic(3, k3=1e9))
        s.add_load(L.Callable(lambda t: np.sin(3.0 * t) * np.arange(6.0)))
        return s

    case("callable-load", callable_load, SA())
    cosine = L.Callable(lambda t: np.cos(5 * t) * np.ones(6))
    case("callable-load-linear", lambda: _linear().add_load(cosine), SA())
    chain4 = lambda: _with(_linear(), *(E.Spring(d, None, k=0.0, k3=2e9) for d in (1, 3, 5)))  # noqa: E731
    for scheme in ("a", "b", "c"):
        for quadrature in ("trapezoid", "parabolic", "exact"):
            integrator = SA(scheme=scheme, quadrature=quadrature, solver="newton")
            case(f"scheme-{scheme}-{quadrature}", chain4, integrator, dt=0.005, x0=x0)
    case("modal-newton", chain4, SA(solver="modal-newton"), x0=x0)
    chain14 = lambda: _with(long(), *(E.Spring(d, None, k=0.0, k3=2e9) for d in (1, 6, 13)))  # noqa: E731
    case("modes3-static-correction", chain14, SA(modes=3))
    case("modes3-no-static-correction", chain14, SA(modes=3, static_correction=False))

    def stiff_friction():
        s = duhamel.System(np.diag([2.0, 1.0]), [[401.0, -400.0], [-400.0, 400.0]], zeta=0.02)
        s.add(E.Callable(fn=_friction, dofs=[0]))
        t = np.linspace(0.0, 4.0, 801)
        s.add_load(L.BaseAcceleration(np.ones(2), t=t, values=4.0 * np.sin(2 * np.pi * 1.3 * t)))
        return s

    case("subdivision-stiff-friction", stiff_friction, SA(max_iter=8), t_end=3.0, dt=0.01)
    case("subdivision-stiff-gap",
         lambda: _with(_linear(), E.Gap(5, None, gap=0.0, k=1e11)), SA(max_iter=4))  # fmt: skip
    # -- mass laws and speed laws
    for name, law, form, scale in (
        ("exponential", Ms.Exponential(rate=-0.1), "momentum", True),
        ("harmonic", Ms.Harmonic(amplitude=0.1, frequency=6.0), "acceleration", False),
        ("tabulated", Ms.Tabulated([0.0, 1.0, 2.5], [1.0, 0.8, 0.9]), "momentum", False),
    ):
        make = lambda law=law, form=form, scale=scale: _linear().set_mass_law(  # noqa: E731
            law, form=form, scale_stiffness=scale
        )
        case(f"mass-{name}", make, SA(), x0=x0)
    case("mass-estimate-with-element",
         lambda: _with(_linear(), E.Cubic(2, k3=1e9)).set_mass_law(Ms.Exponential(rate=-0.2)),
         SA(mass_treatment="estimate"))  # fmt: skip
    runup = S.LinearRunUp(0.0, 300.0, 0.03)
    case("rotor-run-up", lambda: _rotor(runup), SA(), t_end=0.04, dt=1e-4)
    case("rotor-run-up-rub", lambda: _rotor(runup, rub=True), SA(), t_end=0.02, dt=1e-4)

    def scaled_coupling():
        s = duhamel.System(np.eye(2), np.diag([400.0, 500.0]), rayleigh=(0.5, 1e-3))
        G = np.array([[0.0, 0.5], [-0.5, 0.0]])
        s.add(E.LinearCoupling(C=G, scale=S.LinearRunUp(0.0, 100.0, 1.0)))
        law = S.LinearRunUp(0.0, 100.0, 1.0)
        s.add_load(L.Unbalance(**where(L.Unbalance, 0, 1), m_e=1e-3, speed=law))
        return s

    case("scaled-coupling-unbalance", scaled_coupling, SA())
    # -- the direct integrators, dense and sparse, linear and with a Bilinear element
    direct = {
        "newmark": duhamel.Newmark(),
        "hht": duhamel.HHT(-0.1),
        "generalized-alpha": duhamel.GeneralizedAlpha(0.8),
        "central-difference": duhamel.CentralDifference(),
        "cubic-hermite": duhamel.CubicHermite(),
    }

    def model(sparse, bilinear):
        s = _linear("rayleigh")
        if sparse:
            s = duhamel.System(sp.csr_array(s.M), sp.csr_array(s.K), rayleigh=s.rayleigh)
            for load in _linear("rayleigh").loads:
                s.add_load(load)
        if bilinear:
            s.add(E.Bilinear(0, None, k=5e3, fy=20.0, alpha=0.05))
        return s

    for name, integrator in direct.items():
        for sparse in (False, True):
            for bilinear in (False, True):
                tag = f"{name}-{'sparse' if sparse else 'dense'}{'-bilinear' if bilinear else ''}"
                dt = 0.002 if name == "central-difference" else 0.01
                case(tag, lambda sparse=sparse, bilinear=bilinear: model(sparse, bilinear),
                     integrator, dt=dt, x0=x0)  # fmt: skip
    case("newmark-save-dofs", lambda: model(False, False), duhamel.Newmark(), save_every=3,
         dofs=[1, 5], t0=0.2)  # fmt: skip
    return cases


def _other_cases(tmp):
    """Cases that are not one `solve`: a streamed run and resume, an ensemble, spectra."""
    import duhamel
    from duhamel import elements as E

    cases = {}

    def stored():
        try:
            import zarr  # noqa: F401
        except ImportError:
            return {"skipped": np.array("zarr not installed")}
        s = _with(_linear(), E.Bilinear(0, None, k=5e3, fy=20.0, alpha=0.05), E.Cubic(4, k3=1e9))
        path = os.path.join(tmp, "run.zarr")
        sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=30.0, dt=0.01, store=path,
                            checkpoint_every=1)  # fmt: skip
        out = _dump(sol, "stored.")
        out.update(_dump(duhamel.resume(path), "resumed."))
        return out

    cases["store-and-resume"] = stored

    def ensemble():
        from duhamel.ensemble import solve_many

        def make(p):
            s = _linear()
            s.add(E.Bilinear(0, None, k=5e3, fy=p["fy"], alpha=0.05))
            return s

        params = [{"fy": fy} for fy in (5.0, 10.0, 20.0, 40.0)]
        ens = solve_many(make, params, duhamel.Semianalytic(), t_end=2.0, dt=0.01, workers=2)
        out = {}
        for k, sol in enumerate(ens.results):
            out.update(_dump(sol, f"run{k}."))
        return out

    cases["ensemble-threads"] = ensemble

    def spectra():
        from duhamel.records import GroundMotion
        from duhamel.spectra import ductility_spectrum, response_spectrum, rotd

        dt = 0.01
        t = dt * np.arange(1500)
        a1 = 2.0 * np.sin(5.0 * t) * np.exp(-0.2 * t) + 0.7 * np.sin(17.0 * t + 0.3)
        a2 = 1.5 * np.cos(4.0 * t) * np.exp(-0.25 * t) + 0.5 * np.sin(11.0 * t)
        periods = np.geomspace(0.05, 5.0, 9)
        rs = response_spectrum([GroundMotion(a1, dt), GroundMotion(a2, dt)], periods,
                               [0.0, 0.05, 0.2])  # fmt: skip
        r = rotd(GroundMotion(a1, dt), GroundMotion(a2, dt), periods, percentiles=(0, 50, 100))
        ds = ductility_spectrum(GroundMotion(a1, dt), periods[::2], ductility=[1.0, 2.0, 4.0],
                                alpha=0.02)  # fmt: skip
        return {"rs.sd": rs.sd, "rs.sv": rs.sv, "rs.sa": rs.sa, "rotd.sd": r.sd,
                "rotd.peaks": r.peaks, "ductility.uy": ds.uy,
                "ductility.elastic_sd": ds.elastic_sd}  # fmt: skip

    cases["spectra"] = spectra
    return cases


#: Timing phrases of report.md (machine-dependent): left out of the reproduced numbers.
TIMING = re.compile(
    r"per step|loop time|cpu time|computation time|drawn in|\bin [0-9.]+ s\b|"
    r"modes\^|best of|interleaved",
    re.IGNORECASE,
)
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def report_numbers(text):
    """The numbers of report.md's tables, per table row, timing fragments left out: a dict
    'section / claim' -> the row's numbers and verdict as one string."""
    rows, section = {}, ""
    for line in text.splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        if not line.startswith("| ") or line.startswith("|---") or line.startswith("| claim"):
            continue
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
        timed = False
        kept = []
        for cell in cells[1:]:
            for fragment in cell.split(";"):
                if TIMING.search(fragment):
                    timed = True
                else:
                    kept += NUMBER.findall(fragment)
        verdict = "" if timed else (cells[3] if len(cells) > 3 else "")
        rows[f"{section[:12]} / {cells[0]}"] = " ".join(kept) + f" [{verdict}]"
    return rows


def _reproduce(tmp):
    """``duhamel reproduce`` through its command line (the timing example `cpu` left out),
    and the numbers of its report's tables."""
    out_dir = os.path.join(tmp, "reproduce")
    names = "fig1,fig2,fig3,fig4,fig5,fig6,fig7,fig8,rotor,table1"
    done = subprocess.run(
        [sys.executable, "-m", "duhamel", "reproduce", "--out", out_dir, "--only", names,
         "--quiet"],
        env=os.environ.copy(), capture_output=True, text=True, check=False,
    )  # fmt: skip
    if done.returncode != 0:
        raise RuntimeError(f"duhamel reproduce failed ({done.returncode}): {done.stderr[-2000:]}")
    with open(os.path.join(out_dir, "report.md"), encoding="utf-8") as f:
        rows = report_numbers(f.read())
    return {f"row {k:02d} {key[:50]}": np.array(v) for k, (key, v) in enumerate(rows.items())}


def _prepared_solve(again):
    """`solve` through ``prepare(system, integrator, dt=...).run(...)`` (the second run of the
    same Prepared when `again`)."""
    import duhamel

    def solve(system, integrator, *, dt, **kw):
        if set(kw) - {"t_end", "t0", "x0", "v0", "save_every", "dofs"}:
            raise Unsupported(sorted(kw))
        prepared = duhamel.prepare(system, integrator, dt=dt)
        sol = prepared.run(**kw)
        return prepared.run(**kw) if again else sol

    return solve


def worker(out_dir, only):
    """Runs every case (or those named in `only`) with the duhamel on sys.path, saving each
    case's arrays to OUT/<case>.npz; prints one JSON line per case."""
    import tempfile
    import time

    import duhamel

    tmp = tempfile.mkdtemp(prefix="duhamel-check-")
    solves = _cases()
    runs = {name: (lambda f=f: f(duhamel.solve)) for name, f in solves.items()}
    runs.update(_other_cases(tmp))
    runs["reproduce"] = lambda: _reproduce(tmp)
    if hasattr(duhamel, "prepare"):
        for name, f in solves.items():
            runs[name + "+prepared"] = lambda f=f: f(_prepared_solve(False))
            runs[name + "+prepared-again"] = lambda f=f: f(_prepared_solve(True))
    for name, run in runs.items():
        if only and name.split("+")[0] not in only:
            continue
        started = time.perf_counter()
        try:
            arrays = run()
        except Unsupported:
            continue
        except Exception as e:  # the failure is the case's outcome (and what it kept)
            arrays = {"error": np.array(f"{type(e).__name__}: {e}")}
            if getattr(e, "partial", None) is not None:
                arrays.update(_dump(e.partial, "partial."))
        np.savez(os.path.join(out_dir, name + ".npz"), **arrays)
        print(json.dumps({"case": name, "seconds": time.perf_counter() - started}), flush=True)


def identical(a, b):
    """Whether two arrays are the same bits: dtype, shape and bytes (NaNs alike only if
    their payloads are)."""
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def describe(a, b):
    """Why two arrays differ, in a few words."""
    if a.shape != b.shape:
        return f"shape {a.shape} vs {b.shape}"
    if a.dtype != b.dtype:
        return f"dtype {a.dtype} vs {b.dtype}"
    if a.dtype.kind not in "fc":
        return f"{a.ravel()[:1]} vs {b.ravel()[:1]}" if a.size else "differ"
    if np.array_equal(a, b, equal_nan=True):
        return "equal values, other bits (signed zeros or NaN payloads)"
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    diff = np.abs(a - b)[~same]
    return (
        f"{int((~same).sum())} of {a.size} values differ, max abs diff {float(np.nanmax(diff)):.3g}"
    )


def check(args):
    """Runs the cases under both builds (in parallel subprocesses) and compares every array
    bit for bit; returns the exit status (1 on any difference)."""
    import tempfile
    import time

    started = time.perf_counter()
    root = tempfile.mkdtemp(prefix="duhamel-compare-")
    dirs, procs = {}, {}
    for side, path in (("old", args.old), ("new", args.new)):
        dirs[side] = os.path.join(root, side)
        os.makedirs(dirs[side])
        env = dict(os.environ, PYTHONPATH=os.path.abspath(path), OPENBLAS_NUM_THREADS="1")
        cmd = [sys.executable, os.path.abspath(__file__), "--worker", dirs[side]]
        if args.cases:
            cmd += ["--cases", args.cases]
        procs[side] = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True)
    seconds = {}
    for side, proc in procs.items():
        out, _ = proc.communicate()
        if proc.returncode != 0:
            print(f"the {side} build's worker failed (exit {proc.returncode})", file=sys.stderr)
            return 2
        rows = [json.loads(x) for x in out.splitlines() if x.startswith('{"case"')]
        seconds[side] = {row["case"]: row["seconds"] for row in rows}
    old = set(seconds["old"])
    new = set(seconds["new"])
    rows, bad = [], 0
    for name in sorted(new | {n for n in old if "+" not in n}):
        # a prepared twin of the new build is compared with the old build's twin, or with
        # the old plain solve when the old build has no `prepare`
        ref = name if name in old else name.split("+")[0]
        if ref not in old or name not in new:
            rows.append(
                f"| {name} | - | **no**: only in the {'new' if name in new else 'old'} build |"
            )
            bad += 1
            continue
        with (
            np.load(os.path.join(dirs["old"], ref + ".npz")) as a,
            np.load(os.path.join(dirs["new"], name + ".npz")) as b,
        ):
            keys = sorted(set(a.files) | set(b.files))
            problems = [
                f"`{k}` only in the {'new' if k in b.files else 'old'} build"
                if k not in a.files or k not in b.files
                else f"`{k}`: {describe(a[k], b[k])}"
                for k in keys
                if k not in a.files or k not in b.files or not identical(a[k], b[k])
            ]
            raised = str(b["error"])[:70] if "error" in b.files else None
        label = name if ref == name else f"{name} (old: {ref})"
        if problems:
            bad += 1
            more = f"; {len(problems) - 4} more" if len(problems) > 4 else ""
            rows.append(f"| {label} | {len(keys)} | **no**: {'; '.join(problems[:4])}{more} |")
        else:
            rows.append(
                f"| {label} | {len(keys)} | yes{f' (both raise {raised})' if raised else ''} |"
            )
    slowest = sorted(seconds["new"].items(), key=lambda kv: -kv[1])[:3]
    lines = [
        "## Same numbers, bit for bit" + (f": {args.label}" if args.label else ""),
        "",
        "Every array of every case, old build against new (`benchmarks/compare.py --check`):"
        " dtype, shape and bytes. Command:",
        "",
        "```sh",
        shlex.join([".venv/bin/python", "benchmarks/compare.py", *sys.argv[1:]]),
        "```",
        "",
        "| case | arrays | identical? |",
        "|---|---:|---|",
        *rows,
        "",
        f"{len(rows) - bad} of {len(rows)} cases identical, {bad} differ (arrays in {root}); "
        f"{time.perf_counter() - started:.0f} s (the builds in parallel; slowest cases: "
        + ", ".join(f"{k} {v:.1f} s" for k, v in slowest)
        + ").",
        "",
    ]
    print("\n".join(lines))
    if args.append:
        with open(args.append, "a", encoding="utf-8") as f:
            f.write("\n" + "\n".join(lines))
    return 1 if bad else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--old", help="directory holding the old duhamel")
    parser.add_argument("--new", help="directory holding the new duhamel")
    parser.add_argument("--check", action="store_true", help="same numbers, bit for bit?")
    parser.add_argument("--worker", metavar="OUT", help=argparse.SUPPRESS)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cases", help="comma-separated cases (default: all)")
    parser.add_argument("--label", default="", help="what the two builds are, for the report")
    parser.add_argument("--append", metavar="MD", help="append the report to this markdown file")
    args = parser.parse_args()
    only = set(args.cases.split(",")) if args.cases else set()
    if args.worker:
        worker(args.worker, only)
        return
    if not (args.old and args.new):
        parser.error("--old and --new are required")
    if args.check:
        sys.exit(check(args))
    lines = [
        f"## Two builds compared{': ' + args.label if args.label else ''}",
        "",
        "Loop time (`Solution.stats.wall_time`), best of "
        f"{args.repeats} fresh processes per build, the builds alternating. Command:",
        "",
        "```sh",
        shlex.join([".venv/bin/python", "benchmarks/compare.py", *sys.argv[1:]]),
        "```",
        "",
        f"1-min load average before: {os.getloadavg()[0]:.2f}",
        "",
        "| case | old best [s] | new best [s] | new / old |",
        "|---|---:|---:|---:|",
    ]
    print("\n".join(lines), flush=True)
    for case in args.cases.split(",") if args.cases else CASES:
        old, new = [], []
        for _ in range(args.repeats):
            old.append(measure(args.old, case))
            new.append(measure(args.new, case))
        row = f"| {case} | {min(old):.4g} | {min(new):.4g} | {min(new) / min(old):.3f} |"
        print(row, flush=True)
        lines.append(row)
    lines += ["", f"1-min load average after: {os.getloadavg()[0]:.2f}", ""]
    print(lines[-2])
    if args.append:
        with open(args.append, "a") as f:
            f.write("\n" + "\n".join(lines))


if __name__ == "__main__":
    main()
