"""Tests of duhamel.store."""
