"""A damped hardening cubic SDOF under the bundled record, built alike in duhamel and
OpenSees, and its converged response (issue 41's "cubic SDOF under a record to 1e-6").

The model: mass ``M`` = 1 t, linear stiffness ``K`` = 7e4 N/m (period 0.751 s), cubic
stiffness ``K3`` = 2e7 N/m^3 (at the peak of the response, about 0.059 m, the cubic force
equals the linear one: hardening), a linear dashpot ``C`` on the relative velocity, 5 % of
critical on the initial stiffness (OpenSees: mass-proportional Rayleigh damping ``C / M``,
which acts on the relative velocity of its ``UniformExcitation``). The ground acceleration:
:func:`duhamel.demo.synthetic_record` (20 s at 0.01 s, PGA 0.3 g), linear between samples
in the three programs.

* duhamel: ``System(M, K, C)`` with ``elements.Cubic(0, k3=K3)`` and a ``BaseAcceleration``;
* OpenSees: two nodes, a ``zeroLength`` with ``ElasticPowerFunc`` (``-coeff K K3 -exp 1 3``:
  ``K e + K3 e^3`` with its sign), ``UniformExcitation`` of a ``Path`` series, Newmark
  average acceleration, Newton with ``NormDispIncr`` 1e-12, the displacement recorded every
  step (16 digits);
* the reference: scipy ``solve_ivp`` DOP853 at ``rtol`` 1e-12, restarted at every sample of
  the record (where the piecewise-linear record has its kinks).
"""

from __future__ import annotations

import os

import numpy as np
from _materials_system import newmark_transient
from scipy.integrate import solve_ivp

import duhamel
from duhamel.demo import synthetic_record

M = 1.0e3  # kg
K = 7.0e4  # N/m: T = 2 pi sqrt(M / K) = 0.751 s
K3 = 2.0e7  # N/m^3
ZETA = 0.05
C = 2.0 * ZETA * np.sqrt(K * M)  # N s/m
DT_REC = 0.01


def record(seconds: float = 20.0) -> tuple[np.ndarray, np.ndarray]:
    """The bundled record's first `seconds` (its samples ``t`` and ``a`` in m/s^2)."""
    t, a = synthetic_record()
    n = round(seconds / DT_REC) + 1
    return t[:n], a[:n]


def system(t: np.ndarray, a: np.ndarray) -> duhamel.System:
    """duhamel's model under the record (a fresh ``System``)."""
    s = duhamel.System(M * np.eye(1), K * np.eye(1), C * np.eye(1))
    s.add(duhamel.elements.Cubic(0, k3=K3))
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    return s


def run_duhamel(integrator: object, t: np.ndarray, a: np.ndarray, steps: int) -> np.ndarray:
    """The whole call at ``dt = DT_REC / steps``: the displacement at the record's samples."""
    sol = duhamel.solve(system(t, a), integrator, t_end=t[-1], dt=DT_REC / steps, save_every=steps)
    return sol.x[:, 0]


def run_opensees(a: np.ndarray, steps: int, path: str) -> None:
    """OpenSees' transient at ``dt = DT_REC / steps``, its displacement written to `path`."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, M)
    ops.uniaxialMaterial("ElasticPowerFunc", 1, "-coeff", K, K3, "-exp", 1.0, 3.0)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1)
    ops.rayleigh(C / M, 0.0, 0.0, 0.0)
    # 16 digits: the recorder's default 6 would put a floor of about 1e-6 of the peak
    recorder = ("Node", "-file", path, "-precision", 16, "-node", 2, "-dof", 1, "disp")
    if not newmark_transient(ops, a, DT_REC, steps, [recorder]):
        raise RuntimeError(f"OpenSees failed at dt = {DT_REC / steps}")


def read_opensees(path: str, steps: int, n: int) -> np.ndarray:
    """The recorded displacement at the record's `n` samples (zero at the start)."""
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[steps - 1 :: steps]])[:n]


def opensees(a: np.ndarray, steps: int, folder: str) -> np.ndarray:
    """OpenSees' displacement at the record's samples (`folder` holds the recorder's file)."""
    path = os.path.join(folder, f"disp_{steps}.out")
    run_opensees(a, steps, path)
    return read_opensees(path, steps, a.size)


def reference(t: np.ndarray, a: np.ndarray) -> np.ndarray:
    """The converged displacement at the samples: DOP853, rtol 1e-12, restarted at each."""
    y = np.zeros(2)
    xs = [0.0]
    for i in range(t.size - 1):
        t0, t1, a0, a1 = t[i], t[i + 1], a[i], a[i + 1]

        def rhs(s: float, z: np.ndarray, t0=t0, t1=t1, a0=a0, a1=a1) -> list[float]:
            ag = a0 + (a1 - a0) * (s - t0) / (t1 - t0)
            x, v = z
            return [v, -ag - (C * v + K * x + K3 * x**3) / M]

        y = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-15).y[:, -1]
        xs.append(y[0])
    return np.array(xs)
