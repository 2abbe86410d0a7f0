"""Acceleration units of ground-motion records (:data:`UNITS`, :data:`G`) and their
canonical names; re-exported by :mod:`duhamel.records.motion`."""

from __future__ import annotations

from duhamel.constants import STANDARD_GRAVITY

__all__ = ["UNITS", "G"]

#: Standard gravity, m/s^2 (:data:`duhamel.constants.STANDARD_GRAVITY`).
G = STANDARD_GRAVITY

#: Acceleration units understood by the readers, with their factor to m/s^2.
UNITS: dict[str, float] = {
    "g": G,
    "m/s^2": 1.0,
    "cm/s^2": 0.01,
    "gal": 0.01,
    "mm/s^2": 0.001,
    "ft/s^2": 0.3048,
    "in/s^2": 0.0254,
}

_ALIASES = {
    "m/s/s": "m/s^2",
    "m/s2": "m/s^2",
    "m/sec/sec": "m/s^2",
    "m/sec^2": "m/s^2",
    "cm/s/s": "cm/s^2",
    "cm/s2": "cm/s^2",
    "cm/sec/sec": "cm/s^2",
    "cm/sec^2": "cm/s^2",
    "cm/sec2": "cm/s^2",
    "mm/s/s": "mm/s^2",
    "mm/s2": "mm/s^2",
    "mm/sec/sec": "mm/s^2",
    "ft/s/s": "ft/s^2",
    "ft/s2": "ft/s^2",
    "ft/sec/sec": "ft/s^2",
    "in/s/s": "in/s^2",
    "in/s2": "in/s^2",
    "in/sec/sec": "in/s^2",
    "gals": "gal",
}


def _unit(units: str, name: str = "units") -> str:
    """The canonical name of an acceleration unit, or a ValueError naming `name`."""
    if not isinstance(units, str):
        raise TypeError(f"`{name}` must be a string such as 'g' or 'cm/s^2', got {units!r}")
    key = units.strip().lower().replace(" ", "")
    key = _ALIASES.get(key, key)
    if key not in UNITS:
        raise ValueError(f"`{name}` must be one of {sorted(UNITS)} (or an alias), got {units!r}")
    return key
