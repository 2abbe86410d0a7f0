"""Bad input to the record modules (issue 38, third bad-input campaign): records, their
processing, matching, scaling and the target spectra.

Each case of the issue is a test: a value accepted and ignored (a non-integer filter order,
numeric strings through ``float()``, ``zero_end='no'``) is refused by name like the other
parameters of the same function; an allocation the input sizes (filter pads, resampling,
padding, an FFT length) is refused before it starts, naming the parameter and the size; an
internal exception (``AttributeError``, numpy's broadcast error, a message naming another
parameter) is a clear error or, for a valid input, a result.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import duhamel._engine.memory as memory
from duhamel.errors import MatchWarning
from duhamel.records import GroundMotion, GroundMotionPair, match, scale_suite
from duhamel.records.wavelets import TimeDomainStep
from duhamel.spectra import TargetSpectrum, asce7, asce7_multi_period, eurocode8
from duhamel.spectra.response import response_spectrum


@pytest.fixture
def gm() -> GroundMotion:
    """A 10 s record, sampled at 0.01 s."""
    rng = np.random.default_rng(0)
    t = np.arange(1001) * 0.01
    return GroundMotion(rng.standard_normal(1001) * t * np.exp(-t / 3.0) / 5.0, 0.01, "g")


@pytest.fixture
def one_gib(monkeypatch: pytest.MonkeyPatch) -> int:
    """The memory available, as the checks see it: 1 GiB, whatever the machine has."""
    monkeypatch.setattr(memory, "available_memory", lambda: 2**30)
    return 2**30


# -- accepted and ignored ------------------------------------------------------------------


@pytest.mark.parametrize("order", [2.5, 2.0, float("nan"), "2", True])
def test_filter_order_must_be_an_integer(gm, order):
    # 2.5 ran as order 2
    with pytest.raises(TypeError, match="`order` must be an integer"):
        gm.filtered(low=0.1, order=order)


@pytest.mark.parametrize(
    "call",
    [
        lambda gm: gm.filtered(low="0.1"),
        lambda gm: gm.filtered(high="10"),
        lambda gm: gm.bracketed_duration("0.05"),
        lambda gm: gm.resampled("0.01"),
        lambda gm: gm.padded(before="1.0"),
        lambda gm: gm.fourier(smoothing="40"),
        lambda gm: gm.significant_duration("0.05"),
        lambda gm: gm.scaled("2"),
    ],
    ids=["low", "high", "threshold", "dt", "before", "smoothing", "start", "factor"],
)
def test_numeric_strings_are_refused_by_record_methods(gm, call):
    with pytest.raises(TypeError, match=r"^`\w+` must be a real number, got str"):
        call(gm)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: asce7("1.0", 0.6, 8.0), "sds"),
        (lambda: asce7(1.0, "0.6", 8.0), "sd1"),
        (lambda: asce7(1.0, 0.6, "8"), "tl"),
        (lambda: asce7(1.0, 0.6, 8.0, t_max="10"), "t_max"),
        (lambda: eurocode8("0.25", "C"), "ag"),
        (lambda: eurocode8(0.25, "C", importance="1.2"), "importance"),
        (lambda: eurocode8(0.25, "C", damping="0.05"), "damping"),
        (lambda: TargetSpectrum([0.1, 1.0], [1.0, 2.0], damping="0.05"), "damping"),
    ],
)
def test_numeric_strings_are_refused_by_target_spectra(call, name):
    # asce7('1.0', ...) was read through float(), its other parameters' strings not
    with pytest.raises(TypeError, match=f"`{name}` must be a real number, got str"):
        call()


@pytest.mark.parametrize("mce", ["no", 0, None])
def test_mce_must_be_a_bool(mce):
    with pytest.raises(TypeError, match="`mce` must be True or False"):
        asce7(1.0, 0.6, 8.0, mce=mce)
    with pytest.raises(TypeError, match="`mce` must be True or False"):
        asce7_multi_period([0.0, 1.0], [0.5, 0.4], mce=mce)


@pytest.mark.parametrize(
    ("flag", "call"),
    [
        ("zero_end", lambda gm: gm.baseline_corrected(zero_end="no")),
        ("zero_phase", lambda gm: gm.filtered(low=0.1, zero_phase="no")),
        ("keep_padding", lambda gm: gm.filtered(low=0.1, keep_padding=1)),
        ("antialias", lambda gm: gm.resampled(0.02, antialias="no")),
    ],
)
def test_flags_must_be_bools(gm, flag, call):
    # baseline_corrected(zero_end='no') ran with zero_end=True ('no' is truthy)
    with pytest.raises(TypeError, match=f"`{flag}` must be True or False, got"):
        call(gm)


@pytest.mark.parametrize("order", [float("nan"), 3.0, "3"])
def test_baseline_order_must_be_an_integer(gm, order):
    # nan leaked "cannot convert float NaN to integer"
    with pytest.raises(TypeError, match="`order` must be an integer"):
        gm.baseline_corrected(order=order)


def test_rotation_angle_must_be_a_number(gm):
    pair = GroundMotionPair(gm, gm.scaled(0.5))
    with pytest.raises(TypeError, match="`angle` must be a real number, got str"):
        pair.rotated("30")
    with pytest.raises(ValueError, match="`angle` must be finite"):
        pair.rotated(float("inf"))


# -- allocations refused before they start --------------------------------------------------


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda gm: gm.filtered(low=1e-9), "low"),
        (lambda gm: gm.filtered(high=1e-9), "high"),
        (lambda gm: gm.filtered(low=1e-300), "low"),
        (lambda gm: gm.resampled(1e-9), "dt"),
        (lambda gm: gm.resampled(5e-324), "dt"),
        (lambda gm: gm.padded(before=1e9), "before"),
        (lambda gm: gm.padded(after=1e300), "after"),
        (lambda gm: gm.fourier(n_fft=2**40), "n_fft"),
    ],
)
def test_huge_allocations_are_refused_naming_the_parameter(gm, one_gib, call, name):
    # each raised MemoryError (8.7 TiB requested) or OverflowError before
    size = r"samples would take (.*B, more than 50% of the memory available|more memory than)"
    with pytest.raises(ValueError, match=rf"^`{name}` = .*: .* {size}"):
        call(gm)


def test_the_limit_is_the_available_memory_not_a_fixed_size(gm, monkeypatch):
    # padding to `total` samples holds two float64 arrays of it: 16 total bytes, allowed up
    # to half the available memory; one more sample of padding is refused
    pad = 4000
    total = gm.a.size + pad
    monkeypatch.setattr(memory, "available_memory", lambda: 2 * 16 * total)
    out = gm.padded(before=pad * gm.dt)
    assert out.a.size == total and not np.any(out.a[:pad]) and out.a[pad:].tolist() == gm.a.tolist()
    with pytest.raises(ValueError, match=f"`before` = .* {total + 1:.4g} samples would take"):
        gm.padded(before=(pad + 1) * gm.dt)
    monkeypatch.setattr(memory, "available_memory", lambda: None)  # unknown: not refused
    assert gm.padded(before=(pad + 1) * gm.dt).a.size == total + 1


def test_available_memory_is_read_from_the_system():
    avail = memory.available_memory()
    with open("/proc/meminfo", encoding="ascii") as fh:
        total = next(int(line.split()[1]) * 1024 for line in fh if line.startswith("MemTotal:"))
    assert avail is not None and 0 < avail <= total


# -- unclear errors --------------------------------------------------------------------------


def test_fourier_smoothing_is_named_smoothing(gm):
    # said `bandwidth` (the name inside konno_ohmachi)
    with pytest.raises(ValueError, match=r"^`smoothing` must be positive"):
        gm.fourier(smoothing=-1.0)
    with pytest.raises(ValueError, match=r"^`smoothing` must be finite"):
        gm.fourier(smoothing=float("nan"))
    fas = gm.fourier(smoothing=40)
    assert fas.bandwidth == 40.0 and np.all(np.isfinite(fas.smoothed))


@pytest.mark.parametrize("n_fft", [1024.0, "2048", 100])
def test_n_fft_must_be_an_integer_of_at_least_the_record(gm, n_fft):
    with pytest.raises((TypeError, ValueError), match="`n_fft`"):
        gm.fourier(n_fft=n_fft)


def test_scale_suite_target_must_be_a_target_spectrum(gm):
    # AttributeError: 'str' object has no attribute 'periods'
    with pytest.raises(TypeError, match=r"^`target` must be a duhamel.spectra.TargetSpectrum"):
        scale_suite([gm], target="asce7", period_range=(0.1, 1.0))
    with pytest.raises(TypeError, match=r"^`target` must be a duhamel.spectra.TargetSpectrum"):
        match(gm, "asce7", (0.1, 1.0))


@pytest.mark.parametrize(
    ("kwargs", "name", "kind"),
    [
        ({"fraction": "0.9"}, "fraction", TypeError),
        ({"damping": "0.05"}, "damping", TypeError),
        ({"damping": 1.5}, "damping", ValueError),
        ({"n_periods": 10.5}, "n_periods", TypeError),
        ({"minimise_misfit": "yes"}, "minimise_misfit", TypeError),
        ({"period_range": ("0.1", "1.0")}, "period_range", TypeError),
        ({"period_range": (0.1, 0.5, 1.0)}, "period_range", ValueError),
    ],
)
def test_scale_suite_refuses_by_name(gm, kwargs, name, kind):
    args = {"period_range": (0.1, 1.0), **kwargs}
    with pytest.raises(kind, match=f"`{name}`"):
        scale_suite([gm], asce7(1.0, 0.6, 8.0), **args)


@pytest.mark.parametrize(
    ("kwargs", "name", "kind"),
    [
        ({"baseline_order": -1}, "baseline_order", ValueError),  # said `order`
        ({"baseline_order": 2}, "baseline_order", ValueError),  # zero_end needs 3
        ({"baseline_order": 5.0}, "baseline_order", TypeError),
        ({"damping": "0.05"}, "damping", TypeError),
        ({"aim": "1.1"}, "aim", TypeError),
        ({"max_iterations": 2.5}, "max_iterations", TypeError),
        ({"max_iterations": 0}, "max_iterations", ValueError),
        ({"frequency_iterations": -1}, "frequency_iterations", ValueError),
        ({"n_scales": 1}, "n_scales", ValueError),
        ({"prescale": "no"}, "prescale", TypeError),
        ({"tolerance": "0.1"}, "tolerance", TypeError),
        ({"periods": ("0.1", "1.0")}, "periods", TypeError),
    ],
)
def test_match_refuses_by_name(gm, kwargs, name, kind):
    args = {"periods": (0.1, 1.0), **kwargs}
    periods = args.pop("periods")
    with pytest.raises(kind, match=f"`{name}`"):
        match(gm, asce7(1.0, 0.6, 8.0), periods, **args)


def test_match_of_an_all_zero_record_names_the_record():
    # said "`a` contains NaN or inf" (the prescaling divided by a zero spectrum)
    zero = GroundMotion(np.zeros(500), 0.01, name="Z")
    with pytest.raises(ValueError, match=r"^`record` 'Z' is zero at every sample"):
        match(zero, asce7(1.0, 0.6, 8.0), (0.1, 1.0))
    with pytest.raises(ValueError, match="is zero at every sample"):
        match(GroundMotionPair(zero, zero), asce7(1.0, 0.6, 8.0), (0.1, 1.0))


def test_match_over_nearly_the_whole_record_runs(gm):
    # a 10 s record matched over (0.01, 9.9) s: the time-domain stage's oscillators reach
    # beyond the Nyquist frequency, which raised numpy's broadcast error
    target = asce7(1.0, 0.6, 8.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = match(gm, target, (0.01, 9.9), max_iterations=12, frequency_iterations=2)
    info = m.metadata["match"]
    assert info["iterations"] == 12  # the time-domain stage ran its ten adjustments
    assert info["converged"] or any(issubclass(w.category, MatchWarning) for w in caught)
    # what the metadata reports is the returned record's spectrum
    lo, hi = info["range"]
    check = np.geomspace(lo, hi, int(np.ceil(np.log(hi / lo) / np.log(1.01))) + 1)
    ratio = response_spectrum(m, check, 0.05).psa[0, 0] / target(check)
    assert ratio.min() == pytest.approx(info["min_ratio"], rel=1e-12)
    assert ratio.max() == pytest.approx(info["max_ratio"], rel=1e-12)


def test_the_time_domain_stage_stops_at_the_nyquist_frequency():
    periods = np.geomspace(0.01, 1.0, 30)  # 2.5 / 0.01 s = 250 Hz, Nyquist 50 Hz
    step = TimeDomainStep(periods, 1000, 0.01, 0.05)
    assert step.keep == step.n_fft // 2 + 1 == step.omega.size == step.c.size
    assert step.c[0] == step.c[-1] == 1.0 / step.n_fft  # 0 and Nyquist counted once
    coarse = TimeDomainStep(np.geomspace(0.5, 1.0, 5), 1000, 0.01, 0.05)  # 5 Hz: below
    assert coarse.keep < coarse.n_fft // 2 + 1
