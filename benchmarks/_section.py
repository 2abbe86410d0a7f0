"""What every benchmark script shares: its command line (print a markdown section of
BENCHMARKS.md, or append it with ``--append``; ``--quick`` for a smoke run) and a timer."""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable


def main(
    doc: str, section: Callable[[bool], list[str]], quick_help: str, argv: list[str] | None
) -> int:
    """Runs `section(quick)` and prints (and with ``--append FILE`` appends) its lines."""
    parser = argparse.ArgumentParser(description=doc.split("\n")[0])
    parser.add_argument("--append", help="append the section to this markdown file")
    parser.add_argument("--quick", action="store_true", help=quick_help)
    args = parser.parse_args(argv)
    text = "\n".join(section(args.quick)) + "\n"
    print(text)
    if args.append:
        with open(args.append, "a", encoding="utf-8") as f:
            f.write("\n" + text)
    return 0


def timed(f: Callable[[], object]) -> float:
    """Wall time of one call of `f`, in seconds."""
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0
