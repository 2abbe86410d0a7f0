"""The robustness contract over the whole public API: faults, property tests, panics."""
