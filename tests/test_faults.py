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

import numpy as np
import pytest

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
        lambda: duhamel.System(np.eye(2), np.eye(2)).add(E.Cubic(0, 1.0)),
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
