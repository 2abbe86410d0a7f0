"""Rotor faults as force elements: the breathing crack (Gasch's switching crack, Mayes &
Davies' cosine breathing) at a shaft node, in Rust (``crates/duhamel-core/src/elements/
crack.rs``).

The crack is the loss of the shaft's stiffness in the frame turning with the rotor at the
angle ``phi = theta(t) + phase`` (``theta`` of the speed law): with ``xi = x cos(phi) +
y sin(phi)`` (across the crack front) and ``eta = -x sin(phi) + y cos(phi)``, the open crack
lowers the stiffness by `dk_xi` along ``xi`` and `dk_eta` along ``eta``. The element adds
``r = -f R(phi) diag(dk_xi, dk_eta) R(phi)^T (x, y)`` to the uncracked shaft (which the
model's stiffness carries), ``f`` the breathing function: ``"switching"`` ``f = 1`` while
``xi > 0`` (the crack opens under tension; Gasch 1993), ``"cosine"``
``f = (1 + cos(phi)) / 2`` (Mayes & Davies 1984: ``k(phi) = k0 - dk (1 + cos(phi)) / 2``).
"""

from __future__ import annotations

from duhamel._core import BreathingCrack

__all__ = ["BreathingCrack"]
