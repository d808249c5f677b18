"""Compiled kernels on plain arrays: no Python objects, no I/O, no randomness (DESIGN section 3)."""
