"""Tests of duhamel's top-level modules: system, modal, damping, mass, loads, events, speed,
oscillator, prepared, runs, cli."""
