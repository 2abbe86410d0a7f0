"""Tests of duhamel.rotor (and duhamel.rotor.ross against ROSS)."""
