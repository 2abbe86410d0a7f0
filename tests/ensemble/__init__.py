"""Tests of duhamel.ensemble."""
