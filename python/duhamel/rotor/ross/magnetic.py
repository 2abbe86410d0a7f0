"""ROSS's active magnetic bearings (``MagneticBearingElement``) as duhamel's
:class:`~duhamel.rotor.MagneticBearing`: the closed loop with the controller's states
instead of ROSS's frequency-dependent equivalent coefficients.

ROSS linearises the bearing force as ``f = -(k_s x + k_i i)`` with its ``k_s < 0`` (the open
loop's negative stiffness, ``-4 i_0^2 cos(alpha) mu_0 N^2 A / (4 g_0^3)``) and ``k_i > 0``
(Schweitzer & Maslen), the current ``i = k_amp k_sense C(s) x`` (its PID
``C(s) = k_p + k_i,pid / s + k_d s / (1 + s / n_f)``, or a given transfer function), and its
``run_modal`` and ``run_unbalance_response`` take the bearing's dynamic stiffness at the
frequency ``w`` they evaluate it at: ``k_eq(w) + i w c_eq(w) = k_s + k_i k_amp k_sense
C(i w)``, tabulated on the element's ``frequency`` grid (50 points from 1 to 1e4 rad/s by
default) and interpolated between. (Its time-domain routine ``compute_pid_amb`` is a
different, discrete controller; it is not what is mapped.)

duhamel's :class:`MagneticBearing` pushes with ``f = k_s' x - k_i' C'(s) x``, so the map is

    k_s' = -k_s (> 0),   k_i' = k_i,
    C'(s) = Sensor(gain=k_sense) * C(s) * Amplifier(gain=k_amp)

with ``C(s)`` ROSS's PID as :class:`~duhamel.rotor.PID` ``(k_p, k_i,pid, k_d, tau = 1 /
n_f)``, or ROSS's transfer function as a :class:`~duhamel.rotor.StateSpace` (its controllable
canonical form, ``scipy.signal.tf2ss``). Then ``k_i' C'(i w) - k_s'`` is ROSS's ``k_eq +
i w c_eq`` at every frequency (tests/rotor/test_ross_magnetic.py, 1e-12 on ROSS's grid), while
the closed loop's modes come from the controller's states, not from its value at the spin
frequency as ROSS's ``run_modal`` takes it. The sensor-axis rotation of ROSS's element
turns isotropic coefficients into themselves and is not needed. Per-axis gains or bias
currents that differ, and bearings linked to another node, are refused.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

from duhamel.rotor.controllers import PID, Amplifier, Sensor, Series, StateSpace
from duhamel.rotor.magnetic import MagneticBearing

__all__ = ["is_magnetic", "magnetic_bearing", "without_magnetic"]


def is_magnetic(element: Any) -> bool:
    """Whether `element` is a ROSS ``MagneticBearingElement``."""
    ross = sys.modules.get("ross")  # an element of ROSS's: ROSS is loaded
    kind = getattr(ross, "MagneticBearingElement", None)
    return isinstance(kind, type) and isinstance(element, kind)


def _scalar(element: Any, name: str) -> float:
    value = np.atleast_1d(np.asarray(getattr(element, name), dtype=float))
    if value.size and np.all(value == value[0]) and np.isfinite(value[0]):
        return float(value[0])
    raise ValueError(
        f"the ROSS magnetic bearing at node {element.n} has `{name}` = {value.tolist()}: "
        "from_ross maps bearings with the same value on both axes"
    )


def _controller(element: Any) -> Any:
    num = getattr(element, "controller_transfer_function_num", None)
    den = getattr(element, "controller_transfer_function_den", None)
    if num is not None and den is not None:
        import scipy.signal

        num, den = np.atleast_1d(np.asarray(num, float)), np.atleast_1d(np.asarray(den, float))
        if num.size > den.size:
            raise ValueError(
                f"the ROSS magnetic bearing at node {element.n} has an improper controller "
                "transfer function (more zeros than poles): it has no state-space form"
            )
        A, B, C, D = scipy.signal.tf2ss(num, den)
        return StateSpace(A, B.ravel(), C.ravel(), float(np.asarray(D).ravel()[0]))
    kp, ki, kd = (float(getattr(element, f"{g}_pid")) for g in ("kp", "ki", "kd"))
    n_f = float(element.n_f)
    return PID(kp, ki, kd, 1.0 / n_f if kd else 0.0)


def magnetic_bearing(element: Any) -> MagneticBearing:
    """The duhamel bearing of ROSS's ``MagneticBearingElement`` `element` (see the module
    docstring)."""
    if getattr(element, "n_link", None) is not None:
        raise ValueError(
            f"the ROSS magnetic bearing at node {element.n} is linked to node "
            f"{element.n_link}: from_ross maps magnetic bearings to the ground only"
        )
    k_s, k_i = -_scalar(element, "ks"), _scalar(element, "ki")
    if k_s < 0.0 or k_i <= 0.0:
        raise ValueError(
            f"the ROSS magnetic bearing at node {element.n} has k_s = {-k_s:g}, k_i = {k_i:g}: "
            "a pole angle beyond 90 degrees (cos(alpha) <= 0) is not a bearing from_ross maps"
        )
    blocks = [_controller(element)]
    sense, amp = _scalar(element, "k_sense"), _scalar(element, "k_amp")
    if sense != 1.0:
        blocks.insert(0, Sensor(gain=sense))
    if amp != 1.0:
        blocks.append(Amplifier(gain=amp))
    controller = blocks[0] if len(blocks) == 1 else Series(*blocks)
    return MagneticBearing(int(element.n), k_i=k_i, k_s=k_s, controller=controller)


def without_magnetic(rotor: Any, K: Any, C: Any, frequency: float) -> tuple[Any, Any]:
    """ROSS's global `K` and `C` at `frequency` less its magnetic bearings' equivalent
    coefficients there (their closed loops replace them)."""
    K, C = np.array(K, dtype=float), np.array(C, dtype=float)
    for b in getattr(rotor, "bearing_elements", ()):
        if not is_magnetic(b):
            continue
        idx = list(b.dof_global_index.values())
        K[np.ix_(idx, idx)] -= np.asarray(b.K(frequency), dtype=float)
        C[np.ix_(idx, idx)] -= np.asarray(b.C(frequency), dtype=float)
    return K, C
