"""A 10-storey shear building under a synthetic earthquake, with duhamel's public API.

Run:  python examples/shear_building.py [plot.png]      (default: shear_building.png)

The ground acceleration is linear between samples 0.01 s apart and the step is 0.01 s, so
the semi-analytic (Duhamel) integration is exact up to rounding.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import scipy.signal

import duhamel

g = duhamel.STANDARD_GRAVITY  # m/s^2
n, m, h = 10, 2.0e5, 3.5  # storeys, floor mass (kg), storey height (m)

# Storey stiffness tapering from k (ground storey) to k/2 (top), k set for T1 = 1.0 s.
k_rel = np.linspace(1.0, 0.5, n)
K = np.diag(k_rel + np.append(k_rel[1:], 0.0)) - np.diag(k_rel[1:], 1) - np.diag(k_rel[1:], -1)
K *= m * (2 * np.pi / 1.0) ** 2 / np.linalg.eigvalsh(K)[0]
building = duhamel.System(m * np.eye(n), K, zeta=0.05)

# Synthetic record: Kanai-Tajimi filtered white noise, Jennings-type envelope, PGA 0.3 g.
t = np.arange(2001) * 0.01
b, a = scipy.signal.bilinear([2 * 0.6 * 15.0, 15.0**2], [1.0, 2 * 0.6 * 15.0, 15.0**2], fs=100)
ag = scipy.signal.lfilter(b, a, np.random.default_rng(7).standard_normal(t.size))
ag *= np.clip(t / 2.0, 0, 1) ** 2 * np.exp(-0.3 * np.clip(t - 8.0, 0, None)) * (t < 20)
ag *= 0.3 * g / np.abs(ag).max()

building.add_load(duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=ag))
sol = duhamel.solve(building, duhamel.Semianalytic(), t_end=30.0, dt=0.01)

periods = 2 * np.pi / building.modal().omega[:3]
i = np.argmax(np.abs(sol.x[:, -1]))
drift = np.abs(np.diff(sol.x, axis=1, prepend=0.0)).max() / h
shear = np.abs((sol.a + np.interp(sol.t, t, ag, right=0.0)[:, None]).sum(axis=1) * m).max()
print("periods (s):", np.round(periods, 3))
print(f"peak roof displacement {sol.x[i, -1]:+.3f} m at t = {sol.t[i]:.2f} s")
print(f"peak drift ratio {100 * drift:.2f} %, peak base shear {shear / 1e6:.2f} MN")
print(f"{sol.stats.mode_steps_per_second:.3g} mode-steps/s")

fig, axes = plt.subplots(3, 1, figsize=(8, 9), layout="constrained")
axes[0].plot(t, ag / g)
axes[0].set(xlabel="t (s)", ylabel="a_g (g)")
axes[1].plot(sol.t, sol.x[:, -1])
axes[1].set(xlabel="t (s)", ylabel="roof displacement (m)")
axes[2].plot(np.r_[0.0, np.abs(sol.x).max(axis=0)], h * np.arange(n + 1), "o-")
axes[2].set(xlabel="peak displacement (m)", ylabel="height (m)")
out = sys.argv[1] if len(sys.argv) > 1 else "shear_building.png"
fig.savefig(out, dpi=100)
print("wrote", out)
