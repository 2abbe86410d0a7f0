"""Tests of duhamel.analysis."""
