"""Tests of duhamel._engine: the runs of solve on every route."""
