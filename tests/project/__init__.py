"""Repo-wide checks: layout, architecture page, stub, types, README, benchmarks page."""
