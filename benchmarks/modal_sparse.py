"""Times the sparse modal analysis of a large model: one shift-invert factorisation, the
Lanczos iteration, growth of a computed basis, and the free-free case (rigid-body modes).

The model is a 3-D lattice of n x n x n nodes with 3 coupled dofs each (27-point stiffness
and consistent mass stencils, 3 n^3 dofs), fixed at one face or free-free.

    .venv/bin/python benchmarks/modal_sparse.py --nodes 22 --modes 50 100

prints, per case: the time of System() (its check of M), of modal(first), of growing it to
modal(second), of modal(second) on a fresh System, and how many sparse factorisations
(``symmetric_lu``) each made; then /proc/loadavg. The BLAS threads matter on a busy machine:
compare with OPENBLAS_NUM_THREADS=1.
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

import numpy as np


def lattice(n: int, *, free: bool) -> tuple[Any, Any]:
    """Mass and stiffness of the n^3-node lattice (CSR)."""
    import scipy.sparse as sp

    main, off = np.full(n, 2.0), -np.ones(n - 1)
    main[-1] = 1.0
    if free:
        main[0] = 1.0
    lap = sp.diags_array([off, main, off], offsets=[-1, 0, 1], format="csr")
    mass = sp.diags_array(
        [np.full(n - 1, 1 / 6), np.full(n, 4 / 6), np.full(n - 1, 1 / 6)], offsets=[-1, 0, 1]
    ).tocsr()
    lap3 = (
        sp.kron(sp.kron(lap, mass), mass)
        + sp.kron(sp.kron(mass, lap), mass)
        + sp.kron(sp.kron(mass, mass), lap)
    )
    coupling = np.array([[2.0, 0.5, 0.3], [0.5, 2.0, 0.4], [0.3, 0.4, 2.0]])
    K = sp.kron(lap3, coupling, format="csr") * 1e6
    M = sp.kron(sp.kron(sp.kron(mass, mass), mass), sp.identity(3), format="csr") * 2.0
    return M, K


def count_factorisations() -> list[int]:
    """Counts calls of ``symmetric_lu`` wherever duhamel's modules imported it."""
    import duhamel._engine.validate as validate

    calls = [0]
    original = validate.symmetric_lu

    def counted(mat: Any) -> Any:
        calls[0] += 1
        return original(mat)

    for name, module in list(sys.modules.items()):
        if name.startswith("duhamel") and getattr(module, "symmetric_lu", None) is original:
            module.symmetric_lu = counted  # type: ignore[attr-defined]
    return calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nodes", type=int, default=22, help="nodes per edge (3 n^3 dofs)")
    parser.add_argument("--modes", type=int, nargs=2, default=(50, 100), metavar=("N1", "N2"))
    parser.add_argument("--cases", nargs="+", default=["fixed", "free"])
    args = parser.parse_args()
    import duhamel

    calls = count_factorisations()
    first, second = args.modes
    for case in args.cases:
        M, K = lattice(args.nodes, free=case == "free")

        def timed(fn: Any) -> tuple[Any, float, int]:
            before = calls[0]
            start = time.perf_counter()
            out = fn()
            return out, time.perf_counter() - start, calls[0] - before

        system, t_sys, f_sys = timed(lambda M=M, K=K: duhamel.System(M, K))
        _, t1, f1 = timed(lambda s=system: s.modal(first))
        grown, t2, f2 = timed(lambda s=system: s.modal(second))
        other = duhamel.System(M, K)
        fresh, t3, f3 = timed(lambda s=other: s.modal(second))
        dev = np.max(np.abs(grown.omega2 - fresh.omega2) / np.maximum(fresh.omega2, 1.0))
        print(
            f"{case}: n_dof={M.shape[0]}, nnz(K)={K.nnz}; System() {t_sys:.2f} s "
            f"[{f_sys} LU]; modal({first}) {t1:.2f} s [{f1} LU]; grown to modal({second}) "
            f"{t2:.2f} s [{f2} LU]; on a fresh System modal({second}) {t3:.2f} s [{f3} LU]; "
            f"rigid modes {int(np.sum(fresh.omega2 == 0.0))}; "
            f"max rel. |omega2 grown - fresh| {dev:.1e}",
            flush=True,
        )
    with open("/proc/loadavg") as f:
        print("loadavg:", f.read().strip())


if __name__ == "__main__":
    main()
