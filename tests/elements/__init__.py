"""Tests of duhamel.elements."""
