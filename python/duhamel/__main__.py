"""``python -m duhamel``: the :mod:`duhamel.cli` command line."""

from duhamel.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
