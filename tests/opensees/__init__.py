"""Tests of duhamel.opensees."""
