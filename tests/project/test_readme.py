"""The README's Python examples run as written."""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_readme_example_runs(code):
    matplotlib.use("Agg")
    namespace: dict = {}
    exec(compile(code, str(README), "exec"), namespace)
    if "sol" in namespace:
        sol = namespace["sol"]
        assert sol.x.shape[0] == sol.t.size and np.all(np.isfinite(sol.x))


def test_readme_states_the_two_setup_commands():
    text = README.read_text()
    assert "make demo" in text and "make test" in text
    assert len(BLOCKS) >= 2
