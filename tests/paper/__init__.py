"""Tests of duhamel.paper."""
