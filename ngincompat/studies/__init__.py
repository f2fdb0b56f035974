"""Drivers that run scenes many times: the paper, benchmarks, scaling, stability, peer comparison,
sweeps."""
