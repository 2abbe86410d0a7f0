"""Tests of duhamel.spectra."""
