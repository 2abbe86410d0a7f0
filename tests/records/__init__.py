"""Tests of duhamel.records."""
