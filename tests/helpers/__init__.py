"""Shared helpers of the FMPy test suite, the main job and the benchmarks."""
