"""Tests of duhamel.exact."""
