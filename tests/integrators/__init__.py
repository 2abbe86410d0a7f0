"""Tests of duhamel.integrators."""
