"""The example scripts run (smoke tests, so they cannot rot)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_duffing_quadratures_prints_the_table():
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "duffing_quadratures.py")],
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    ).stdout
    assert "1000 steps" in out and "506 steps" in out
    row_b = next(line for line in out.splitlines() if line.strip().startswith("b "))
    trapezoid, parabolic, _exact = (float(v) for v in row_b.split()[1:])
    assert trapezoid < parabolic and abs(trapezoid - 0.0348) < 5e-4
