"""``_engine`` passes ``mypy --strict`` (issue 35; the pinned mypy of the test tools, the
configuration in pyproject.toml), so that CI checks what ``make lint`` checks."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_engine_passes_mypy_strict() -> None:
    pytest.importorskip("mypy", reason="mypy is among the test tools (make install)")
    done = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "python/duhamel/_engine"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-2000:]
    assert "Success" in done.stdout
