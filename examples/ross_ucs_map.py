"""The undamped critical speed map of ROSS's compressor (``ross.compressor_example()``,
56 nodes, two bearings and twelve seals) through ``from_ross``: critical speeds against the
bearing stiffness (the seals left out, as ROSS's ``run_ucs``), the bearings' ``kxx``/``kyy``
curves from ROSS's interpolants over it, and their intersections.

Needs ROSS (``pip install ross-rotordynamics``).

    python examples/ross_ucs_map.py                       # prints the intersections
    python examples/ross_ucs_map.py --save docs/figures    # writes ross_ucs_map.png
"""

from __future__ import annotations

import argparse
import contextlib
import io
import warnings
from pathlib import Path

import numpy as np

from duhamel.rotor import from_ross


def run(n_k: int = 41) -> object:
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency, the file's ROSS version
        import ross

        rotor = ross.compressor_example()
    model = from_ross(rotor, 0.0)
    return model.rotor.critical_speed_map(
        np.logspace(6, 10, n_k), n_modes=4, speeds=np.linspace(0.0, 2000.0, 201)
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--save", help="directory for the figure")
    args = parser.parse_args()
    ucs = run()
    for p in ucs.intersections:
        print(f"bearing {p.node} {p.direction}: mode {p.mode} at {p.speed:.1f} rad/s, "
              f"k = {p.stiffness:.3g} N/m")  # fmt: skip
    if args.save:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 4.5))
        ucs.plot(ax)
        ax.set_title("ROSS compressor: undamped critical speed map")
        fig.tight_layout()
        fig.savefig(Path(args.save) / "ross_ucs_map.png", dpi=90)


if __name__ == "__main__":
    main()
