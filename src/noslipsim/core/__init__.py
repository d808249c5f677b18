"""Compiled kernels on plain arrays: no Python objects, no I/O, no randomness.

Nothing here imports from the layers above it (scenes, simulate, analysis, ...).
"""
