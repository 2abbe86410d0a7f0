"""A large FE model from MatrixMarket files, with a few nonlinear springs: the large-model route.

FE packages export their mass and stiffness matrices as MatrixMarket files (``.mtx``:
Abaqus ``*MATRIX GENERATE``, ANSYS ``HBMAT``/``mmwrite``, Code_Aster, OpenSees' ``printA``
through scipy). This example builds a 3-D lattice (30 x 30 x 33 = 29,700 dofs: unit masses,
springs to the six neighbours, the bottom layer on springs to the ground), writes M and K
with ``scipy.io.mmwrite`` as an FE package would, reads them back with ``scipy.io.mmread``
and passes the COO matrices straight to ``duhamel.System``. Ten cubic springs at random
dofs make it nonlinear; a harmonic force at a top corner drives it. The run keeps 100
modes (one shift-invert eigsh), which the static correction enriches with the springs' and
the load's static responses, and takes 1e4 steps of 1 ms.

The modal basis is saved next to the matrices (``ModalBasis.save``) and reused by a second
``System`` with the same M and K: the second run skips the modal analysis.

Usage::

    python examples/lattice_mmread.py           # the 29,700-dof model
    python examples/lattice_mmread.py --small   # 8 x 8 x 8 (the test)
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

import duhamel
from duhamel import elements as E
from duhamel import loads as L


def lattice(shape: tuple[int, int, int], k: float = 1e4) -> tuple[sp.csr_array, sp.csr_array]:
    """Unit masses, springs `k` to the six neighbours, the bottom layer tied to the ground."""
    index = np.arange(int(np.prod(shape))).reshape(shape)
    pairs = [np.moveaxis(index, axis, 0) for axis in range(3)]
    i = np.concatenate([a[:-1].ravel() for a in pairs])
    j = np.concatenate([a[1:].ravel() for a in pairs])
    n = index.size
    links = sp.coo_array((np.full(i.size, k), (i, j)), shape=(n, n))
    degree = np.bincount(i, minlength=n) + np.bincount(j, minlength=n)
    ground = np.zeros(n)
    ground[index[:, :, 0].ravel()] = k
    stiffness = sp.diags(k * degree + ground) - links - links.T
    return sp.identity(n, format="csr"), sp.csr_array(stiffness)


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--small", action="store_true", help="an 8 x 8 x 8 lattice")
    parser.add_argument("--steps", type=int, default=10_000)
    args = parser.parse_args(argv)
    shape, modes = ((8, 8, 8), 30) if args.small else ((30, 30, 33), 100)
    M, K = lattice(shape)
    n = M.shape[0]
    out: dict = {"n_dof": n}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        scipy.io.mmwrite(folder / "M.mtx", M, symmetry="symmetric")
        scipy.io.mmwrite(folder / "K.mtx", K, symmetry="symmetric")
        M_read, K_read = scipy.io.mmread(folder / "M.mtx"), scipy.io.mmread(folder / "K.mtx")
        out["format"] = type(K_read).__name__

        def model() -> duhamel.System:
            system = duhamel.System(M_read, K_read, zeta=0.02)
            system.add_load(L.Harmonic(n - 1, amplitude=100.0, omega=6.0))
            rng = np.random.default_rng(3)
            for dof in rng.choice(n - 1, size=10, replace=False):
                system.add(E.Cubic(int(dof), k3=1e9))
            return system

        started = time.perf_counter()
        first = model()
        basis = first.modal(modes)
        out["modal_seconds"] = time.perf_counter() - started
        basis.save(folder / "basis.npz")

        kw = {"t_end": args.steps * 1e-3, "dt": 1e-3, "dofs": [n - 1]}
        sol = duhamel.solve(first, duhamel.Semianalytic(modes=modes), **kw)
        second = model().use_basis(duhamel.ModalBasis.load(folder / "basis.npz"))
        started = time.perf_counter()
        again = duhamel.solve(second, duhamel.Semianalytic(modes=modes), **kw)
        out["second_total_seconds"] = time.perf_counter() - started
    out.update(solution=sol, again=again, coordinates=sol.stats.modes)
    per_step = 1e6 * sol.stats.wall_time / sol.stats.steps
    print(
        f"{n:,} dofs read from MatrixMarket ({out['format']}); modal analysis ({modes} modes) "
        f"{out['modal_seconds']:.1f} s; run: {sol.stats.modes} coordinates ({modes} modes + "
        f"static correction), {per_step:.1f} us per step, {sol.stats.total_time:.2f} s in all; "
        f"second System on the saved basis: {out['second_total_seconds']:.2f} s in all; peak "
        f"tip displacement {np.abs(sol.x).max():.4g} m"
    )
    return out


if __name__ == "__main__":
    main()
