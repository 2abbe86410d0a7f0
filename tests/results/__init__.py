"""Tests of duhamel.results."""
