"""Campbell diagrams with mode tracking through crossings, and speed-dependent bearings.

``pytest -s tests/rotor/test_rotor_tracking.py`` prints the measured numbers (docs/rotor.md).

References share nothing with the code under test: the whirl of a disk on a massless
Timoshenko shaft in closed form (statics of the beam on its bearings, as in test_rotor.py),
and, for the speed-dependent bearings, rotors built with constant bearings holding the
coefficients of each speed (computed here, not by the bearing's interpolation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import duhamel
from duhamel.rotor import Bearing, Disk, Material, Rotor, Shaft
from duhamel.rotor.bearing import TableRangeWarning

# the tables are evaluated beyond their ends on purpose (the end values are held):
# tests/rotor/test_rotor_bearing_tables.py checks the warning
pytestmark = pytest.mark.filterwarnings("ignore::duhamel.rotor.bearing.TableRangeWarning")

E_MOD, NU = 211e9, 0.3
G_MOD = E_MOD / (2 * (1 + NU))
MAT = Material(E=E_MOD, rho=7810.0, nu=NU)
EPS = float(np.finfo(float).eps)

# --------------------------------------------------------------------------------------------
# 1. Mode tracking: a gyroscopic disk at mid-span of a massless shaft, in closed form
# --------------------------------------------------------------------------------------------
L, D, MASS, IP, ID, KB = 0.8, 0.04, 30.0, 0.3, 0.16, 5e6


def jeffcott(*extra: Bearing) -> tuple[Rotor, float, float]:
    """The rotor and the disk's translational and tilt support stiffnesses ``kt``, ``kr``.

    Statics of the Timoshenko beam (simply supported on the bearings, load at mid-span):
    compliances ``L^3/(48 EI) + L/(4 kGA) + 1/(2 k_b)`` and ``L/(12 EI) + 1/(kGA L) +
    2/(k_b L^2)``; by symmetry translation and tilt decouple. Translation whirls at
    ``sqrt(kt/m)`` forward and backward at every speed; the tilt whirl ``e^{i w t}`` solves
    ``Id w^2 - Ip Omega w - kr = 0`` (``w > 0`` forward, ``w < 0`` backward).
    """
    shaft = Shaft(L / 2, D, material=Material(E=E_MOD, rho=0.0, nu=NU))
    rotor = Rotor(
        [shaft, shaft], [Disk(1, MASS, IP, ID)], [Bearing(0, KB, KB), Bearing(2, KB, KB), *extra]
    )
    EI, kga = E_MOD * shaft.second_moment, shaft.kappa * G_MOD * shaft.area
    ct = L**3 / (48 * EI) + L / (4 * kga) + 1 / (2 * KB)
    cr = L / (12 * EI) + 1 / (kga * L) + 2 / (KB * L**2)
    return rotor, 1 / ct, 1 / cr


def tilt_branch(kr: float, speed: float, sense: int) -> float:
    """The tilt whirl frequency of the branch with orbit sense ``+1`` (from +x to +y) or -1:
    ``|w|`` for the root of ``Id w^2 - Ip Omega w - kr = 0`` with ``sign(w) = sense``."""
    root = math.sqrt((IP * speed) ** 2 + 4 * ID * kr)
    return (sense * IP * speed + root) / (2 * ID)


def test_tracked_branches_match_the_closed_form_through_the_crossing():
    """The backward tilt whirl falls from sqrt(kr/Id) through the translational pair
    sqrt(kt/m) (forward and backward) at Omega* = (kr - Id wt^2)/(Ip wt). The grid holds
    Omega* itself (three equal eigenvalues there)."""
    rotor, kt, kr = jeffcott()
    wt = math.sqrt(kt / MASS)
    w_cross = (kr - ID * wt**2) / (IP * wt)
    speeds = np.linspace(0.0, 2.5 * w_cross, 26)  # speeds[10] == w_cross (to round-off)
    assert abs(speeds[10] / w_cross - 1) < 1e-15
    assert tilt_branch(kr, 0.0, -1) > 5 * wt and tilt_branch(kr, speeds[-1], -1) < 0.5 * wt

    campbell = rotor.campbell(speeds)
    assert campbell.tracked and campbell.frequencies.shape == (26, 4)
    ref = np.empty_like(campbell.frequencies)
    for j in range(4):
        (label,) = set(campbell.whirl[:, j])  # one whirl label per column, at every speed
        tilt = campbell.frequencies[0, j] > 2 * wt
        sense = 1 if label == "forward" else -1
        ref[:, j] = [tilt_branch(kr, w, sense) if tilt else wt for w in speeds]
    labels = sorted(
        (
            ("tilt " if campbell.frequencies[0, j] > 2 * wt else "translation ")
            + campbell.whirl[0, j]
        )
        for j in range(4)
    )
    assert labels == [
        "tilt backward",
        "tilt forward",
        "translation backward",
        "translation forward",
    ]
    err = float(np.max(np.abs(campbell.frequencies / ref - 1)))
    worst_mac = 1 - float(np.nanmin(campbell.mac))
    print(f"\nclosed form vs tracked branches: worst relative error {err:.1e}")
    print(f"1 - MAC of the matched pairs: at most {worst_mac:.1e}")
    assert err <= 1e-12
    assert worst_mac <= 1e-12
    assert np.isnan(campbell.mac[0]).all()

    # untracked: ascending at every speed, so the tilt-backward column changes hands
    sorted_ = rotor.campbell(speeds, track=False)
    assert not sorted_.tracked
    assert np.all(np.diff(sorted_.frequencies, axis=1) >= 0)
    assert np.array_equal(np.sort(campbell.frequencies, axis=1), sorted_.frequencies)
    assert set(sorted_.whirl[:, 0]) == {"backward", "forward"}  # branches swap in column 0
    j_tb = int(np.flatnonzero(ref[-1] < 0.5 * wt)[0])  # tracked: the tilt-backward column
    assert j_tb == 2 and campbell.frequencies[-1, 2] == sorted_.frequencies[-1, 0]


def test_tracking_walks_the_speeds_in_ascending_order_and_keeps_the_given_order():
    rotor, _, kr = jeffcott()
    speeds = np.linspace(0.0, 1e4, 21)
    shuffled = np.random.default_rng(3).permutation(speeds)
    a, b = rotor.campbell(speeds), rotor.campbell(shuffled)
    order = np.argsort(shuffled)
    assert np.array_equal(b.speeds, shuffled)
    for name in ("frequencies", "damping_ratios", "mac"):
        assert np.array_equal(getattr(b, name)[order], getattr(a, name), equal_nan=True), name
    assert np.array_equal(b.whirl[order], a.whirl)
    # the MAC of the lowest speed is NaN wherever that row sits
    assert np.isnan(b.mac[order[0]]).all() and not np.isnan(b.mac[order[1:]]).any()

    # through zero speed a branch keeps its orbit sense; its label relative to the spin flips
    speeds = np.linspace(-6000.0, 6000.0, 25)
    campbell = rotor.campbell(speeds)
    (j,) = [j for j in range(4) if campbell.frequencies[-1, j] > 5000.0]  # fastest at +6000
    ref = [tilt_branch(kr, w, 1) for w in speeds]  # the +x -> +y tilt orbit, for every speed
    err = float(np.max(np.abs(campbell.frequencies[:, j] / ref - 1)))
    print(f"\nbranch through zero speed vs closed form: {err:.1e}")
    assert err <= 1e-12
    assert set(campbell.whirl[speeds < 0, j]) == {"backward"}
    assert set(campbell.whirl[speeds > 0, j]) == {"forward"}


def shaft_rotor(**kw) -> Rotor:
    """Four shaft elements with mass, a disk at mid-span, damped cross-coupled bearings (all
    isotropic): its tilt mode's backward whirl falls through the translational mode's forward
    and backward whirl (not degenerate: the shaft's own gyroscopic terms split them)."""
    b = {"kxy": 2e5, "kyx": -2e5, "cxx": 300.0, "cyy": 300.0}
    return Rotor(
        [Shaft(0.25, 0.05, material=MAT)] * 4,
        [Disk(2, 30.0, 0.6, 0.3)],
        [Bearing(0, 1e7, 1e7, **b), Bearing(4, 1e7, 1e7, **b)],
        **kw,
    )


def test_tracked_branches_are_smooth_where_sorted_columns_kink():
    """No closed form. Tracked columns keep their whirl and are smooth: their largest second
    difference on a uniform grid falls as h^2 under refinement. Sorted columns kink where
    branches cross: theirs falls as h (the jump in slope times h)."""
    rotor = shaft_rotor(rayleigh=(0.0, 1e-5))
    kinks: dict[bool, list[float]] = {True: [], False: []}
    for n in (81, 161, 321):
        speeds = np.linspace(0.0, 8000.0, n)
        tracked = rotor.campbell(speeds, n_modes=4)
        sorted_ = rotor.campbell(speeds, n_modes=4, track=False)
        assert tracked.frequencies.shape == sorted_.frequencies.shape == (n, 4)
        assert np.all(np.diff(sorted_.frequencies, axis=1) >= 0)
        assert np.array_equal(np.sort(tracked.frequencies, axis=1), sorted_.frequencies)
        for j in range(4):
            assert len(set(tracked.whirl[1:, j])) == 1, j
        # the untracked second-lowest column holds two branches, the tracked ones one each
        assert set(sorted_.whirl[1:, 1]) == {"backward", "forward"}
        assert np.nanmin(tracked.mac) > 0.99
        assert np.nanmin(sorted_.mac) < 1e-6  # a swap: unrelated shapes in one column
        for track, c in ((True, tracked), (False, sorted_)):
            kinks[track].append(float(np.abs(np.diff(c.frequencies, 2, axis=0)).max()))
    for track, expected in ((True, 2.0), (False, 1.0)):
        orders = np.log2(np.array(kinks[track][:-1]) / kinks[track][1:])
        print(
            f"\n{'tracked' if track else 'sorted'}: max |second difference| "
            f"{np.round(kinks[track], 3).tolist()} rad/s for h = 100, 50, 25 rad/s; "
            f"orders {np.round(orders, 3).tolist()}"
        )
        assert np.all(np.abs(orders - expected) <= 0.1), (track, orders)


def test_n_modes_window_with_tracking():
    """n_modes = 2: the falling tilt-backward branch enters the window where it crosses the
    second mode, which leaves it; three columns, two values per row, same as untracked."""
    rotor = shaft_rotor()
    speeds = np.linspace(0.0, 6000.0, 61)
    tracked = rotor.campbell(speeds, n_modes=2)
    sorted_ = rotor.campbell(speeds, n_modes=2, track=False)
    assert sorted_.frequencies.shape == (61, 2) and tracked.frequencies.shape == (61, 3)
    finite = np.isfinite(tracked.frequencies)
    assert np.all(finite.sum(axis=1) == 2)
    assert np.array_equal(np.sort(tracked.frequencies[finite].reshape(61, 2)), sorted_.frequencies)
    labels = [set(tracked.whirl[finite[:, j], j]) for j in range(3)]
    assert all(len(s) == 1 for s in labels)
    # the backward translation stays; the forward translation leaves where the falling
    # tilt-backward branch (the last column: it enters last) comes in
    (stay,) = [j for j in range(3) if finite[:, j].all()]
    (leave,) = [j for j in range(3) if finite[0, j] and not finite[-1, j]]
    assert leave < 2 and labels[stay] == {"backward"} and labels[leave] == {"forward"}
    enter = int(np.argmax(finite[:, 2]))
    assert enter > 0 and labels[2] == {"backward"}
    assert finite[enter:, 2].all() and not finite[:enter, 2].any()
    assert finite[:enter, leave].all() and not finite[enter:, leave].any()
    print(f"\nn_modes=2: the tilt-backward branch enters at {speeds[enter]:.0f} rad/s")


def test_modes_that_appear_and_disappear_end_their_branches():
    """A speed-dependent damper on the disk (k = 0) overdamps the translation at the ends of
    the range: m x'' + c(Omega) x' + kt x = 0, damped frequency sqrt(kt/m - (c/2m)^2) while
    c < 2 sqrt(kt m). The tilt modes are untouched (closed form)."""
    _, kt, kr = jeffcott()
    c_crit = 2 * math.sqrt(kt * MASS)
    table = [0.0, 2000.0, 6000.0, 8000.0]
    c_table = [3 * c_crit, 0.3 * c_crit, 0.3 * c_crit, 3 * c_crit]
    damper = Bearing(1, 0.0, 0.0, cxx=c_table, cyy=c_table, speeds=table, interpolation="linear")
    rotor, _, _ = jeffcott(damper)
    speeds = np.linspace(0.0, 8000.0, 41)
    c = np.interp(speeds, table, c_table)
    assert np.min(np.abs(c / c_crit - 1)) > 0.05  # no speed near critical damping
    oscillating = c < c_crit
    assert not oscillating[0] and oscillating.any() and not oscillating[-1]

    campbell = rotor.campbell(speeds)
    assert campbell.frequencies.shape == (41, 4)
    counts = np.isfinite(campbell.frequencies).sum(axis=1)
    assert np.array_equal(counts, [rotor.modes(w).n_modes for w in speeds])
    wd = np.sqrt(kt / MASS - (c / (2 * MASS)) ** 2, where=oscillating, out=np.zeros_like(c))
    worst = 0.0
    for j in range(4):
        present = np.isfinite(campbell.frequencies[:, j])
        (label,) = set(campbell.whirl[present, j])
        if j < 2:  # present at the lowest speed: the tilt pair, all along
            assert present.all()
            ref = np.array([tilt_branch(kr, w, 1 if label == "forward" else -1) for w in speeds])
        else:  # the translation: one branch each, from where it appears to where it ends
            assert np.array_equal(present, oscillating)
            ref = np.where(present, wd, np.nan)
        worst = max(worst, float(np.nanmax(np.abs(campbell.frequencies[:, j] / ref - 1))))
        assert np.isnan(campbell.mac[~present, j]).all()
    assert sorted(campbell.whirl[oscillating][0, 2:]) == ["backward", "forward"]
    print(f"\nappearing/disappearing translation, tilt: worst relative error {worst:.1e}")
    assert worst <= 1e-12
    sorted_ = rotor.campbell(speeds, track=False)
    assert np.array_equal(np.isfinite(sorted_.frequencies).sum(axis=1), counts)


def test_campbell_arguments():
    rotor, _, _ = jeffcott()
    with pytest.raises(ValueError, match="`n_modes` must be a positive integer"):
        rotor.campbell([0.0, 100.0], n_modes=0)
    with pytest.raises(TypeError, match="`track` must be a bool"):
        rotor.campbell([0.0, 100.0], track="yes")
    with pytest.raises(ValueError, match="`speeds`"):
        rotor.campbell([0.0, np.nan])
    empty = rotor.campbell([])
    assert empty.frequencies.shape == (0, 0) and empty.mac.shape == (0, 0)
    modes = rotor.modes(100.0)
    with pytest.raises(ValueError, match="degrees of freedom"):
        modes.mac(shaft_rotor().modes(100.0))
    # MAC is 1 with itself, 0 between the forward and backward circular translation
    mac = modes.mac(modes)
    assert np.allclose(np.diag(mac), 1.0, rtol=0, atol=4 * EPS)
    forward, backward = modes.whirl.index("forward"), modes.whirl.index("backward")
    assert mac[forward, backward] <= 4 * EPS


# --------------------------------------------------------------------------------------------
# 2. Speed-dependent bearing coefficients
# --------------------------------------------------------------------------------------------
TABLE = [100.0, 300.0, 600.0]
COEFFS = {
    "kxx": [1.0e7, 2.0e7, 4.0e7],
    "kyy": [1.5e7, 2.5e7, 5.0e7],
    "kxy": [1.0e6, 3.0e6, 8.0e6],
    "kyx": [-2.0e6, -5.0e6, -1.2e7],
    "cxx": [6.0e3, 4.0e3, 3.0e3],
    "cyy": [7.0e3, 5.0e3, 3.5e3],
    "cxy": [50.0, 80.0, 100.0],
    "cyx": [-60.0, -90.0, -120.0],
}


def coefficients_at(speed: float) -> dict[str, float]:
    """The table written out: held below and above it, linear in between."""
    if speed <= TABLE[0]:
        return {k: v[0] for k, v in COEFFS.items()}
    if speed >= TABLE[-1]:
        return {k: v[-1] for k, v in COEFFS.items()}
    i = int(np.searchsorted(TABLE, speed)) - 1
    t = (speed - TABLE[i]) / (TABLE[i + 1] - TABLE[i])
    return {k: (1 - t) * v[i] + t * v[i + 1] for k, v in COEFFS.items()}


def fluid_rotor(bearing_at, **kw) -> Rotor:
    """Two disks on a shaft with mass; a tabulated bearing at node 0, a constant one at 5
    (``bearing_at(node)`` builds the one at node 0)."""
    return Rotor(
        [Shaft(0.2, 0.04, material=MAT) for _ in range(5)],
        [Disk.from_geometry(2, 0.05, 0.25, 0.04, MAT), Disk.from_geometry(4, 0.04, 0.2, 0.04, MAT)],
        [bearing_at(0), Bearing(5, 2e7, 3e7, kxy=1e6, kyx=-1.5e6, cxx=2e3, cyy=2e3)],
        **kw,
    )


def tabulated(node: int, **extra) -> Bearing:
    return Bearing(node, **COEFFS, speeds=TABLE, interpolation="linear", **extra)


def constant(speed: float):
    return lambda node, **extra: Bearing(node, **coefficients_at(speed), **extra)


@pytest.mark.parametrize("damping", [{"rayleigh": (2.0, 1e-5)}, {"zeta": 0.02}])
def test_speed_dependent_matrices_are_the_table_interpolated(damping):
    """Rotor.matrices at the table points equal those of the constant bearing exactly, and
    between / outside them the linear interpolation / end values (the structural damping
    depends on K_sym, so on the bearing, too)."""
    rotor = fluid_rotor(tabulated, **damping)
    assert rotor.has_speed_dependent_bearings
    worst = dict.fromkeys("MKCG", 0.0)
    for speed in [*TABLE, 0.0, 50.0, 150.0, 299.0, 450.0, 1000.0, -300.0]:
        got = rotor.matrices(speed)
        ref = fluid_rotor(constant(speed), **damping).matrices(speed)
        on_table = speed in TABLE or speed < TABLE[0] or speed > TABLE[-1]
        for name, a, b in zip("MKCG", got, ref, strict=True):
            if on_table:  # the same coefficients: the same matrices, bit for bit
                assert np.array_equal(a, b), (name, speed)
            diff = float(np.abs(a - b).max() / np.abs(b).max())
            worst[name] = max(worst[name], diff)
    print(f"\nmatrices, tabulated vs constant bearings ({damping}): worst {worst}")
    assert worst["M"] == worst["G"] == 0.0 and worst["K"] <= 4 * EPS
    assert worst["C"] <= (4 * EPS if "rayleigh" in damping else 1e-13)
    # constant-coefficient rotors keep their cached matrices
    plain = fluid_rotor(constant(300.0), **damping)
    assert not plain.has_speed_dependent_bearings
    assert np.array_equal(plain.matrices(0.0).K, plain.matrices(1e4).K)


def test_bearing_interpolation():
    b = tabulated(3)
    assert b.is_speed_dependent and b.speeds == tuple(TABLE)
    assert b.kxx == tuple(COEFFS["kxx"])
    for speed in (*TABLE, 20.0, 200.0, 555.0, 1e5):
        c = coefficients_at(speed)
        k, d = b.stiffness_at(speed), b.damping_at(speed)
        ref_k = np.array([[c["kxx"], c["kxy"]], [c["kyx"], c["kyy"]]])
        ref_d = np.array([[c["cxx"], c["cxy"]], [c["cyx"], c["cyy"]]])
        if speed in TABLE or speed < TABLE[0] or speed > TABLE[-1]:
            assert np.array_equal(k, ref_k) and np.array_equal(d, ref_d)
        assert np.abs(k - ref_k).max() <= 4 * EPS * np.abs(ref_k).max()
        assert np.abs(d - ref_d).max() <= 4 * EPS * np.abs(ref_d).max()
    with pytest.raises(ValueError, match=r"node 3 .*speed-dependent.*stiffness_at\(speed\)"):
        _ = b.stiffness
    with pytest.raises(ValueError, match=r"node 3 .*damping_at\(speed\)"):
        _ = b.damping
    # a partly tabulated bearing; constants stay floats; tuples keep equality and hashing
    part = Bearing(1, kxx=[1e7, 2e7], kyy=3e7, cxy=-5.0, speeds=[0, 100])
    assert part.kyy == 3e7 and part.cxy == -5.0 and part.stiffness_at(50.0)[0, 0] == 1.5e7
    assert part == Bearing(1, kxx=np.array([1e7, 2e7]), kyy=3e7, cxy=-5.0, speeds=(0.0, 100.0))
    assert len({part, Bearing(1, kxx=[1e7, 2e7], kyy=3e7, cxy=-5.0, speeds=[0, 100])}) == 1
    # `speeds` with constant coefficients only: a constant bearing
    flat = Bearing(1, 1e7, 2e7, speeds=[0, 100])
    assert not flat.is_speed_dependent and flat.stiffness.tolist() == [[1e7, 0.0], [0.0, 2e7]]
    # existing calls are unchanged
    old = Bearing(0, 1e9, 1e9, 1e7, -1e7, 5.0, 6.0, 0.5, -0.5, 0.1, 2e-5, (1e-4, 1e8))
    assert old.speeds is None and not old.is_speed_dependent and old.contact == (1e-4, 1e8, 0.0)
    assert old.damping.tolist() == [[5.0, 0.5], [-0.5, 6.0]]
    assert np.array_equal(old.stiffness_at(123.0), old.stiffness)


def test_speed_dependent_campbell_equals_constant_bearings_at_each_speed():
    """Campbell (tracked and sorted), modes, natural frequencies and the static deflection
    of the tabulated rotor against rotors with constant bearings at each speed."""
    rotor = fluid_rotor(tabulated, rayleigh=(0.0, 2e-5))
    speeds = np.linspace(0.0, 800.0, 33)  # below, through and above the table
    sorted_ = rotor.campbell(speeds, n_modes=8, track=False)
    tracked = rotor.campbell(speeds, n_modes=8)
    shown = np.isfinite(tracked.frequencies)
    assert np.all(shown.sum(axis=1) == 8)
    assert np.array_equal(np.sort(tracked.frequencies[shown].reshape(-1, 8)), sorted_.frequencies)
    worst_f = worst_z = 0.0
    for i, w in enumerate(speeds):
        ref = fluid_rotor(constant(w), rayleigh=(0.0, 2e-5))
        modes = ref.modes(w, n=8)
        worst_f = max(
            worst_f, float(np.max(np.abs(sorted_.frequencies[i] / modes.frequencies - 1)))
        )
        worst_z = max(
            worst_z, float(np.max(np.abs(sorted_.damping_ratios[i] - modes.damping_ratios)))
        )
        assert tuple(sorted_.whirl[i]) == modes.whirl
        assert np.array_equal(rotor.modes(w, n=8).frequencies, sorted_.frequencies[i])
        assert np.array_equal(rotor.natural_frequencies(w, n=8), sorted_.frequencies[i])
        static, static_ref = rotor.static_deflection(speed=w), ref.static_deflection(speed=w)
        assert np.abs(static - static_ref).max() <= 1e-13 * np.abs(static_ref).max()
    print(
        f"\nCampbell, tabulated vs constant bearings: frequencies {worst_f:.1e} (relative), "
        f"damping ratios {worst_z:.1e} (absolute)"
    )
    assert worst_f <= 1e-12 and worst_z <= 1e-12
    # the table matters: at its top speed, against its first coefficients held constant
    first = fluid_rotor(constant(TABLE[0]), rayleigh=(0.0, 2e-5))
    change = rotor.natural_frequencies(TABLE[-1], n=8) / first.natural_frequencies(TABLE[-1], 8)
    print(f"frequency change at {TABLE[-1]:g} rad/s due to the table: up to {change.max():.2f}x")
    assert change.max() > 1.5


def test_speed_dependent_system_and_cubic_law():
    """Rotor.system at a constant speed uses the coefficients of that speed: the same
    background, couplings and cubic elements (x_stat from the static deflection at that
    speed, k3 from kxx, kyy there) as the rotor with constant bearings."""
    speed = 450.0
    rotor = fluid_rotor(lambda n: tabulated(n, beta=0.1), rayleigh=(0.0, 1e-5))
    ref = fluid_rotor(lambda n: constant(speed)(n, beta=0.1), rayleigh=(0.0, 1e-5))
    got_sys, ref_sys = rotor.system(speed), ref.system(speed)
    assert repr(got_sys) == repr(ref_sys)
    for name in ("M", "K", "C"):
        a, b = getattr(got_sys, name), getattr(ref_sys, name)
        assert np.abs(a - b).max() <= 4 * EPS * np.abs(b).max(), name
    kinds = [type(e).__name__ for e in got_sys.elements]
    assert kinds == [type(e).__name__ for e in ref_sys.elements]
    for a, b in zip(got_sys.elements, ref_sys.elements, strict=True):
        if type(a).__name__ == "Cubic":
            assert a.dof == b.dof and abs(a.k3 / b.k3 - 1) <= 1e-13
        elif type(a).__name__ == "LinearCoupling":
            for m in ("K", "C"):
                x, y = getattr(a, m), getattr(b, m)
                assert (x is None) == (y is None)
                if x is not None:
                    assert np.abs(x - y).max() <= 4 * EPS * np.abs(y).max()
    cubic = [e for e in got_sys.elements if type(e).__name__ == "Cubic"]
    assert len(cubic) == 2
    # k3 = kxx(speed) beta / x_stat^2, x_stat the bearing's vertical deflection at that speed
    x_stat = abs(rotor.static_deflection(speed=speed)[rotor.dof(0, "y")])
    kxx = coefficients_at(speed)["kxx"]
    assert abs(cubic[0].k3 / (kxx * 0.1 / x_stat**2) - 1) <= 1e-13
    assert rotor.static_deflection(speed=speed)[1] != rotor.static_deflection(speed=100.0)[1]
    with pytest.raises(ValueError, match=r"cubic law of the bearing at node 0 .*give `speed`"):
        tabulated(0, beta=0.1, x_stat=1e-5).elements(0, 1)


def test_speed_dependent_bearings_follow_a_run_up():
    """A run-up through the table: the bearing coefficients follow the speed law (PCHIP or
    linear, as Bearing.stiffness_at); against DOP853 on the ODE written out here with
    ``K(omega(t))``, ``C(omega(t))`` from Bearing.stiffness_at / damping_at, second order."""
    from scipy.integrate import solve_ivp

    rotor = fluid_rotor(lambda n: Bearing(n, **COEFFS, speeds=TABLE))
    w0, w1, t1 = 150.0, 550.0, 0.04
    run_up = duhamel.speed.LinearRunUp(omega0=w0, omega1=w1, t1=t1)
    system = rotor.system(run_up)
    n = rotor.n_dof
    Minv = np.linalg.inv(rotor.mass_matrix)
    d = [rotor.dof(0, "x"), rotor.dof(0, "y")]
    table = rotor.bearings[0]
    _, K_rest, C_rest, G = rotor.matrices(w0)  # all but the tabulated bearing
    K_rest[np.ix_(d, d)] -= table.stiffness_at(w0)
    C_rest[np.ix_(d, d)] -= table.damping_at(w0)
    f = np.zeros(n)
    f[rotor.dof(2, "x")], f[rotor.dof(2, "y")] = 1e3, -5e2
    x0 = np.linalg.solve(rotor.matrices(w0).K, f)  # released from a static deflection

    def rhs(t, z):
        w = w0 + (w1 - w0) * min(t / t1, 1.0)
        K, C = K_rest.copy(), C_rest.copy()
        K[np.ix_(d, d)] += table.stiffness_at(w)
        C[np.ix_(d, d)] += table.damping_at(w)
        x, v = z[:n], z[n:]
        return np.r_[v, -Minv @ (K @ x + (C + w * G) @ v)]

    ref = solve_ivp(rhs, (0.0, t1), np.r_[x0, np.zeros(n)], method="DOP853", rtol=1e-10,
                    atol=1e-15, dense_output=True)  # fmt: skip
    translations = np.r_[0:n:4, 1:n:4]
    errors = []
    for dt in (1e-4, 5e-5):
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=t1, dt=dt, x0=x0)
        exact = ref.sol(sol.t)[:n].T[:, translations]
        errors.append(float(np.abs(sol.x[:, translations] - exact).max() / np.abs(exact).max()))
    print(f"\nrun-up through the table (PCHIP): {errors}")
    assert errors[1] < 3e-5
    assert 2.8 < errors[0] / errors[1] < 4.5  # second order
    # the element follows the law with the bearing's own interpolation, PCHIP or linear
    for kind in ("pchip", "linear"):
        b = Bearing(0, **COEFFS, speeds=TABLE, interpolation=kind)
        r = fluid_rotor(lambda n, b=b: b)
        (table_el,) = [
            e
            for e in r.system(run_up).elements
            if isinstance(e, duhamel.elements.SpeedTableBearing)
        ]
        for t in (0.0, 0.013, 0.029, 0.05):
            w = w0 + (w1 - w0) * min(t / t1, 1.0)
            got = table_el.evaluate(np.array([1.0, 0.0]), np.zeros(2), t)[0]
            want = b.stiffness_at(w)[:, 0] - b.stiffness_at(w0)[:, 0]
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * abs(want).max() + 1e-6)
    # a constant law is a constant speed
    a = rotor.system(duhamel.speed.ConstantSpeed(450.0))
    b = rotor.system(450.0)
    assert np.array_equal(a.K, b.K) and np.array_equal(a.C, b.C)
    # beyond the table: warned, the end values held
    with pytest.warns(TableRangeWarning, match="beyond the table"):
        rotor.system(duhamel.speed.LinearRunUp(omega0=0.0, omega1=900.0, t1=1.0))


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        (
            {"kxx": [1e7, 2e7], "speeds": [0, 1, 2]},
            ValueError,
            r"`kxx` has 2 values but `speeds` has 3",
        ),
        ({"cyx": [1.0, 2.0, 3.0, 4.0], "speeds": [0, 1, 2]}, ValueError, r"`cyx` has 4 values"),
        (
            {"kxx": [1e7, 2e7, 3e7], "speeds": [0, 2, 1]},
            ValueError,
            r"`speeds` must be strictly ascending, got speeds\[2\] = 1 after speeds\[1\] = 2",
        ),
        ({"kxx": [1e7, 2e7], "speeds": [5, 5]}, ValueError, r"`speeds` must be strictly ascending"),
        ({"kxx": [1e7, 2e7], "speeds": [0, np.nan]}, ValueError, r"`speeds` contains NaN"),
        ({"kxx": [1e7, 2e7], "speeds": []}, ValueError, r"`speeds` must hold at least one"),
        ({"kxx": [1e7, 2e7], "speeds": [[0, 1]]}, ValueError, r"`speeds` must be a 1-D array"),
        (
            {"kxy": [1e7, np.nan], "speeds": [0, 1]},
            ValueError,
            r"`kxy` must be finite, got nan at speeds\[1\] = 1 rad/s",
        ),
        (
            {"kyy": [1e7, -1.0], "speeds": [0, 1]},
            ValueError,
            r"`kyy` must be non-negative at every speed, got -1.0 at speeds\[1\] = 1",
        ),
        (
            {"cxx": [-5.0, 1.0], "speeds": [0, 1]},
            ValueError,
            r"`cxx` must be non-negative at every speed, got -5.0 at speeds\[0\]",
        ),
        ({"cyy": [1.0, -1.0], "speeds": [0, 1]}, ValueError, r"`cyy` must be non-negative"),
        (
            {"kxx": [1e7, 2e7]},
            ValueError,
            r"`kxx` is a table of 2 values, but the bearing has no `speeds`",
        ),
        ({"kxx": [[1e7, 2e7]], "speeds": [0, 1]}, ValueError, r"`kxx` must be a 1-D array"),
        ({"kxx": ["a", "b"], "speeds": [0, 1]}, TypeError, r"`kxx`"),
        ({"kxx": -1.0}, ValueError, r"`kxx` must be non-negative, got -1.0"),
        ({"cxy": np.inf}, ValueError, r"`cxy` must be finite"),
    ],
)
def test_bearing_validation(kwargs, error, match):
    args = {"kxx": 1e7, "kyy": 1e7, **kwargs}
    with pytest.raises(error, match=match):
        Bearing(0, **args)
