"""Tests of duhamel.design."""
