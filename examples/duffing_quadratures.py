"""Duffing oscillator (the paper's section 4.1): error of each scheme and quadrature.

Prints the maximum displacement error against the exact cn solution for x'' + x + 4 x^3 = 0,
x0 = 1, v0 = 0, omega dt = 2 pi/100, over 1000 steps (10 periods of the linear background)
and over 506 steps (10 periods of the Duffing oscillator). Run:

    python examples/duffing_quadratures.py
"""

import numpy as np

import duhamel
from duhamel.exact import duffing


def main() -> None:
    dt = 2 * np.pi / 100
    for label, t_end in [("1000 steps", 20 * np.pi), ("506 steps", 10 * 3.179723)]:
        print(f"max |x - x_exact| / x0, {label}")
        print("scheme  trapezoid  parabolic  exact")
        for scheme in "abc":
            errors = []
            for quadrature in ("trapezoid", "parabolic", "exact"):
                system = duhamel.System(np.eye(1), np.eye(1)).add(duhamel.elements.Cubic(0, k3=4.0))
                options = duhamel.Semianalytic(scheme=scheme, quadrature=quadrature)
                sol = duhamel.solve(system, options, t_end=t_end, dt=dt, x0=[1.0])
                exact, _ = duffing(sol.t, 1.0, 4.0, 1.0)
                errors.append(np.abs(sol.x[:, 0] - exact).max())
            print(f"{scheme:>6}  " + "  ".join(f"{e:9.4f}" for e in errors))


if __name__ == "__main__":
    main()
