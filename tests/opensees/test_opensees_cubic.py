"""The hardening cubic SDOF of ``benchmarks/cubic_opensees.py`` (tests/_support/_cubic_record.py)
solves the same model in OpenSees and in duhamel: OpenSees' converged transient
(``ElasticPowerFunc`` ``K e + K3 e^3`` in a ``zeroLength``, Newmark average acceleration at
``dt = 0.01 / 64``, its own error estimated from the run at twice the step) equals duhamel's
fourth-order and second-order runs, and the restarted DOP853 reference, to 1e-5 of the peak
over the whole record."""

from __future__ import annotations

import numpy as np
import pytest
from _cubic_record import K3, K, opensees, record, reference, run_duhamel

import duhamel

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees  # noqa: F401
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, np.ndarray]:
    t, a = record()
    folder = str(tmp_path_factory.mktemp("cubic"))
    return {
        "opensees": opensees(a, 64, folder),
        "opensees_2dt": opensees(a, 32, folder),
        "hermite": run_duhamel(duhamel.Semianalytic(scheme="hermite"), t, a, 4),
        "second": run_duhamel(duhamel.Semianalytic(), t, a, 64),
        "reference": reference(t, a),
    }


def test_the_cubic_force_matters_at_the_peak(runs):
    x = np.abs(runs["reference"]).max()
    assert 0.5 < K3 * x**3 / (K * x) < 2.0


def test_opensees_is_converged_to_a_few_millionths_of_the_peak(runs):
    """Second order: the difference from the run at twice the step is 3 times its error."""
    peak = np.abs(runs["opensees"]).max()
    assert np.abs(runs["opensees"] - runs["opensees_2dt"]).max() / 3 < 6e-6 * peak


@pytest.mark.parametrize("route", ["hermite", "second", "reference"])
def test_opensees_and_duhamel_give_the_same_transient(runs, route):
    peak = np.abs(runs["reference"]).max()
    assert runs["opensees"].size == runs[route].size == 2001
    assert np.abs(runs["opensees"] - runs[route]).max() < 1e-5 * peak
