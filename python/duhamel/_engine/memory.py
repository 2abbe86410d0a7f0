"""How much memory an allocation may take: the allocations whose size the user's input sets
(a record padded by a filter, a dense eigendecomposition of a large model) are refused
before they start when they would not fit, instead of ending in a ``MemoryError`` deep
inside numpy or in a crash of the process (LAPACK, the operating system's OOM killer).

The limit is a fraction of the memory available to the process: the operating system's
estimate (``MemAvailable`` of ``/proc/meminfo`` on Linux, ``os.sysconf`` elsewhere), lowered
to what a cgroup (a container's memory limit) still allows. Where neither is known, nothing
is refused.
"""

from __future__ import annotations

import os

__all__ = ["MEMORY_FRACTION", "SMALL_ALLOCATION", "available_memory", "check_fits", "format_bytes"]

#: The share of the available memory one allocation may take (the rest is the caller's, the
#: other arrays of the run and the operating system's).
MEMORY_FRACTION = 0.5

#: Bytes below which an allocation is never refused, without asking the operating system
#: (reading ``/proc/meminfo`` and the cgroup files costs ~0.07 ms, a quarter of a short
#: run's overhead): a process that cannot find 128 KiB is beyond saving by this check.
SMALL_ALLOCATION = 64 * 1024


def _read(path: str) -> str | None:
    try:
        with open(path, encoding="ascii") as fh:
            return fh.read()
    except (OSError, ValueError):
        return None


def _meminfo() -> int | None:
    text = _read("/proc/meminfo")
    if text is None:
        return None
    for line in text.splitlines():
        if line.startswith("MemAvailable:"):
            parts = line.split()
            return int(parts[1]) * 1024 if len(parts) >= 2 and parts[1].isdigit() else None
    return None


def _sysconf() -> int | None:
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, OSError, ValueError):
        return None


def _cgroup() -> int | None:
    """What a cgroup v2 memory limit still allows (None without a limit)."""
    limit = _read("/sys/fs/cgroup/memory.max")
    used = _read("/sys/fs/cgroup/memory.current")
    if limit is None or used is None or not limit.strip().isdigit():
        return None
    try:
        return max(0, int(limit.strip()) - int(used.strip()))
    except ValueError:
        return None


def available_memory() -> int | None:
    """Bytes of memory available to this process now, or None when unknown."""
    known = [v for v in (_meminfo() or _sysconf(), _cgroup()) if v is not None]
    return min(known) if known else None


def format_bytes(n: float) -> str:
    """``n`` bytes in binary units: ``'8.73 TiB'``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024.0 or unit == "PiB":
            return f"{n:.3g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024.0
    raise AssertionError  # pragma: no cover - the loop returns


def check_fits(nbytes: float, what: str, advice: str) -> None:
    """ValueError when `nbytes` exceed :data:`MEMORY_FRACTION` of :func:`available_memory`:
    ``"{what} would take {size}, more than ... available: {advice}"``. `what` names the
    parameter that sets the size (in backticks) and the size in elements. Allocations of at
    most :data:`SMALL_ALLOCATION` bytes pass without a look at the system's memory."""
    if 0.0 <= nbytes <= SMALL_ALLOCATION:
        return
    available = available_memory()
    if nbytes != nbytes or nbytes == float("inf"):  # beyond any memory
        shown = "more memory than exists"
        raise ValueError(f"{what} would take {shown}: {advice}")
    if available is None or nbytes <= MEMORY_FRACTION * available:
        return
    raise ValueError(
        f"{what} would take {format_bytes(nbytes)}, more than {MEMORY_FRACTION:.0%} of the "
        f"memory available ({format_bytes(available)}): {advice}"
    )
